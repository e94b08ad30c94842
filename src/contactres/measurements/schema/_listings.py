"""The tables of the forward computations: printed listings and the data of the papers' figures.

* :data:`CONTACT_TABLE`: ``contactres contact`` (job ``contact``), one row per (R, F, f);
* :data:`DCSF_TABLE`: ``contactres dcsf`` (job ``dcsf``), one row per (model, k a);
* :data:`QCM_LOOP_TABLE`: ``contactres qcm loop`` (job ``qcm_loop``), one row per amplitude;
* :data:`CRYSTAL_TABLE`: :func:`contactres.crystal_table` (``crystals.csv`` of
  ``contactres demo``) and :data:`CRYSTALS_LISTING`, the same with the indentation moduli of
  three faces (``contactres crystals``, job ``crystals``);
* :data:`PAPER1_RANKING`: ``paper1_model_ranking.csv`` of ``contactres figures paper1``;
* :data:`PAPER2_LOOPS`, :data:`PAPER2_TURNING`, :data:`PAPER2_SHIFTS`: the loops of paper 2's
  Fig. 2C-D (``paper2_fig2_loops.csv``), their turning points, and Fig. 1D
  (``paper2_fig1d_shifts.csv``) of ``contactres figures paper2``.

Some columns are written only in some cases (a frequency given, a tangential stiffness asked
for); their meaning says when. ``tests/jobs/test_job_schemas.py`` runs the jobs and compares
the columns of each table with these.
"""

from __future__ import annotations

from ._columns import Column, TableSchema

__all__ = [
    "CONTACT_TABLE",
    "CRYSTALS_LISTING",
    "CRYSTAL_TABLE",
    "DCSF_TABLE",
    "EXAMPLES_LISTING",
    "PAPER1_RANKING",
    "PAPER2_LOOPS",
    "PAPER2_SHIFTS",
    "PAPER2_TURNING",
    "QCM_LOOP_TABLE",
]


def _columns(*rows: tuple[str, str, str]) -> tuple[Column, ...]:
    """Output columns from (name, unit, meaning) rows."""
    return tuple(Column(name, unit, meaning) for name, unit, meaning in rows)


#: ``contactres contact``: the Hertz contact of a rigid sphere on a crystal face (paper 1,
#: Eqs. 1-4; an ellipse on a face without 3- or 4-fold symmetry), with its dynamic normal and
#: tangential stiffness when asked for; on a coated face (``--coating``) the axisymmetric
#: contact on the layered solid.
CONTACT_TABLE = TableSchema(
    "contact listing",
    "one row per (sphere radius, force, frequency): the contact and its stiffness",
    _columns(
        ("radius_m", "m", "sphere radius R"),
        ("force_N", "N", "normal force F"),
        (
            "contact_radius_m",
            "m",
            "contact radius: √(ab) of the contact ellipse, the Hertz a on a face with 3- or "
            "4-fold symmetry (coated: of the layered solid, axisymmetric)",
        ),
        (
            "semi_major_m",
            "m",
            "semi-axis a of the contact ellipse, a >= b (Willis 1966; bare face only)",
        ),
        ("semi_minor_m", "m", "semi-axis b of the contact ellipse (bare face only)"),
        ("ellipticity", "-", "b/a, 1 for a circular contact (bare face only)"),
        (
            "orientation_deg",
            "deg",
            "angle of the major axis from the surface x axis (`--inplane`), positive towards y, "
            "in (−90, 90]; 0 for a circular contact (bare face only)",
        ),
        ("peak_pressure_Pa", "Pa", "pressure p0 at the centre of the contact (3F/(2πab))"),
        ("depth_m", "m", "indentation depth δ"),
        ("stiffness_N_per_m", "N/m", "static normal contact stiffness K_sa = dF/dδ"),
        (
            "indentation_modulus_Pa",
            "Pa",
            "indentation modulus M of the face (paper 1, Eq. 4); coated: M(a) = K_sa/(2a)",
        ),
        (
            "coating",
            "text",
            "the films on the face, top first, e.g. `PMMA 250 nm` (with `--coating`)",
        ),
        (
            "film_share",
            "-",
            "1 − K_sa(coated)/K_sa(bare face) at the same force: how much of the contact "
            "stiffness the film takes (< 0: a film stiffer than the face); empty without "
            "contact (with `--coating`)",
        ),
        (
            "tangential_stiffness_N_per_m",
            "N/m",
            "static tangential stiffness K_t of the contact (with `--tangential`, no frequency)",
        ),
        ("frequency_Hz", "Hz", "oscillation frequency f (with `--frequency`)"),
        ("ks_a", "-", "k_s a = ω a √(ρ/C44) of the (substrate's) face (with `--frequency`)"),
        (
            "dynamic_stiffness_real_N_per_m",
            "N/m",
            "Re K_da = K_sa Re DCSF, exact model, lossless solid; coated: the layered flat "
            "punch at a, films at f (with `--frequency`)",
        ),
        ("dynamic_stiffness_imag_N_per_m", "N/m", "Im K_da (with `--frequency`)"),
        (
            "tangential_stiffness_real_N_per_m",
            "N/m",
            "Re K_t at the frequency (with `--frequency` and `--tangential`)",
        ),
        (
            "tangential_stiffness_imag_N_per_m",
            "N/m",
            "Im K_t at the frequency: waves radiated (with `--frequency` and `--tangential`)",
        ),
        (
            "tangential_loss_tangent",
            "-",
            "Im K_t/Re K_t, empty without contact (with `--frequency` and `--tangential`)",
        ),
        (
            "flags",
            "text",
            "a contact wider than Hertz's small-contact theory allows: `a/R = … > 0.1: Hertz "
            "approximate` (values kept) or `a/R = … > 0.5: beyond Hertz, no value` (values "
            "empty: check the radius and the force); present only when a row is flagged",
        ),
    ),
)

#: ``contactres dcsf``: the DCSF of each model against k a (paper 1, Eq. 29). With
#: ``--format csv`` or ``json`` the command adds the face's C33_over_C44, C33_Pa, C44_Pa,
#: v_l_m_per_s and v_s_m_per_s to every row (the job keeps them apart, as values).
DCSF_TABLE = TableSchema(
    "dcsf listing",
    "one row per (model, k a): the dynamic contact stiffness factor DCSF = K_da/K_sa",
    _columns(
        ("ka", "-", "normalised wave number k a: k_l a or k_s a (`--wavenumber`)"),
        ("model", "text", "displacement model (exact, WA, WA2D, TP, SA, R0, R1)"),
        ("re", "-", "Re DCSF"),
        ("im", "-", "Im DCSF (the radiation damping)"),
        (
            "rel_error",
            "-",
            "estimated relative error of the DCSF: its difference from a refined evaluation",
        ),
        (
            "flags",
            "text",
            "';'-separated: not-converged (rel_error above `--rtol` after every refinement), "
            "negative-damping (Im DCSF < 0, no passive contact has it); empty: none",
        ),
        ("radius_m", "m", "sphere radius R (with `--radius/--force/--frequency`)"),
        ("force_N", "N", "static force F (with `--radius/--force/--frequency`)"),
        ("frequency_Hz", "Hz", "frequency f (with `--radius/--force/--frequency`)"),
        (
            "contact_radius_m",
            "m",
            "static Hertz contact radius a, √(ab) of the contact ellipse on a face without 3- or "
            "4-fold symmetry (with `--radius/...`)",
        ),
        ("stiffness_N_per_m", "N/m", "static contact stiffness K_sa (with `--radius/...`)"),
        ("K_re_N_per_m", "N/m", "Re K = K_sa Re DCSF (with `--radius/...`)"),
        ("K_im_N_per_m", "N/m", "Im K = K_sa Im DCSF (with `--radius/...`)"),
        (
            "coating",
            "text",
            "the films on the face, top first, e.g. `PMMA 250 nm` (with `--coating`: the DCSF "
            "of the layered punch at a and f; ka is then the substrate's)",
        ),
    ),
)

#: ``contactres qcm loop``: the shifts of a QCM loaded by partial-slip contacts (paper 2,
#: Eqs. 4-5).
QCM_LOOP_TABLE = TableSchema(
    "qcm loop listing",
    "one row per amplitude: the shifts and the effective stiffness of one contact",
    _columns(
        ("u0_m", "m", "oscillation amplitude u0"),
        ("df_Hz", "Hz", "frequency shift Δf (paper 2, Eq. 4)"),
        ("dgamma_Hz", "Hz", "shift of the half-bandwidth ΔΓ (paper 2, Eq. 5)"),
        ("K1_N_per_m", "N/m", "K′ = Δf/P of one contact (P the sensitivity of the resonator)"),
        ("K2_N_per_m", "N/m", "K″ = ΔΓ/P of one contact"),
    ),
)

#: :func:`contactres.crystal_table`: the built-in solids (``crystals.csv`` of the demo).
CRYSTAL_TABLE = TableSchema(
    "crystals.csv",
    "one row per built-in solid; empty where a column does not apply to its symmetry",
    _columns(
        ("name", "text", "name of the solid (`--crystal NAME`)"),
        ("c11_GPa", "GPa", "elastic constant c11 (of an isotropic solid: from E and ν)"),
        ("c12_GPa", "GPa", "elastic constant c12"),
        ("c44_GPa", "GPa", "elastic constant c44"),
        ("c13_GPa", "GPa", "elastic constant c13 (trigonal)"),
        ("c14_GPa", "GPa", "elastic constant c14 (trigonal)"),
        ("c33_GPa", "GPa", "elastic constant c33 (trigonal)"),
        ("density_kg_m3", "kg/m^3", "mass density ρ"),
        ("symmetry", "text", "cubic, trigonal or isotropic"),
        ("E_GPa", "GPa", "Young's modulus E (isotropic solids)"),
        ("nu", "-", "Poisson's ratio ν (isotropic solids)"),
        ("zener", "-", "Zener ratio A = 2 c44/(c11 − c12) (cubic and isotropic)"),
        ("poisson", "-", "cubic Poisson parameter c12/(c11 + c12) (cubic and isotropic)"),
        ("source", "text", "where the constants come from"),
    ),
)

#: ``contactres crystals``: :data:`CRYSTAL_TABLE` with the indentation moduli M of three faces
#: (paper 1, Eq. 4: a rigid sphere sees an isotropic E* = M) before the source.
CRYSTALS_LISTING = TableSchema(
    "crystals listing",
    "one row per built-in solid, with the indentation moduli of its faces",
    (
        *CRYSTAL_TABLE.columns[:-1],
        *_columns(
            ("M001_GPa", "GPa", "indentation modulus M of the face normal to the crystal z axis"),
            ("M011_GPa", "GPa", "M of the cubic (011) face (cubic and isotropic)"),
            ("M111_GPa", "GPa", "M of the cubic (111) face (cubic and isotropic)"),
        ),
        CRYSTAL_TABLE.column("source"),
    ),
)

#: ``contactres examples``: the example files installed with contactres.
EXAMPLES_LISTING = TableSchema(
    "examples listing",
    "one row per example file installed with contactres (contactres.examples)",
    _columns(
        ("name", "text", "file name"),
        ("size_bytes", "bytes", "size of the file"),
        ("description", "text", "what the file holds"),
        ("command", "text", "a command that reads it, run from a folder holding a copy"),
        ("extra", "text", "the optional extras that command needs, comma separated; empty: none"),
        ("path", "text", "where it is installed, or where it was copied to"),
    ),
)

#: ``paper1_model_ranking.csv``: each displacement model against the exact rigid punch.
PAPER1_RANKING = TableSchema(
    "paper1_model_ranking.csv",
    "one row per (Zener ratio, model): the largest relative error against the exact punch",
    _columns(
        ("zener", "-", "Zener ratio A of the cubic solid (ν = 0.25, Q⁻¹ = 0.02)"),
        ("model", "text", "displacement model (WA, R0, R1, SA, TP, WA2D)"),
        ("max_rel_error_kla_le_1", "-", "max |DCSF/DCSF_exact − 1| over k_l a <= 1"),
        ("max_rel_error_kla_le_2", "-", "max |DCSF/DCSF_exact − 1| over k_l a <= 2"),
        ("rank_kla_le_1", "-", "rank of the model at that A over k_l a <= 1 (1: closest)"),
    ),
)

#: ``paper2_fig2_loops.csv``: the force-displacement loops of paper 2's Fig. 2C-D.
PAPER2_LOOPS = TableSchema(
    "paper2_fig2_loops.csv",
    "the loops of one contact, 201 points per (model, amplitude)",
    _columns(
        ("model", "text", "voigt (linear, with dashpot) or cattaneo_mindlin (no dashpot)"),
        ("u0_m", "m", "amplitude u0 of the loop"),
        ("u_m", "m", "tangential displacement u, from −u0 to u0"),
        ("F_plus_N", "N", "tangential force on the branch of increasing u"),
        ("F_minus_N", "N", "tangential force on the branch of decreasing u"),
    ),
)

#: The turning points of the loops of :data:`PAPER2_LOOPS` (drawn, not written).
PAPER2_TURNING = TableSchema(
    "paper2 turning points",
    "one row per (model, amplitude): the force at the turning point of the loop",
    _columns(
        ("model", "text", "as in the loops"),
        ("u0_m", "m", "amplitude u0"),
        ("F_u0_N", "N", "tangential force F(u0) at the turning point (Δf ∝ F(u0)/u0)"),
    ),
)

#: ``paper2_fig1d_shifts.csv``: Δf(u0) and ΔΓ(u0) of paper 2's Fig. 1D.
PAPER2_SHIFTS = TableSchema(
    "paper2_fig1d_shifts.csv",
    "one row per amplitude: the shifts of both partial-slip models, same dashpot",
    _columns(
        ("u0_m", "m", "oscillation amplitude u0"),
        ("df_cm_Hz", "Hz", "Δf of Cattaneo-Mindlin contacts (paper 2, Eq. 6)"),
        ("dgamma_cm_Hz", "Hz", "ΔΓ of Cattaneo-Mindlin contacts"),
        ("df_savkoor_Hz", "Hz", "Δf of Savkoor contacts (paper 2, Eqs. 13-14)"),
        ("dgamma_savkoor_Hz", "Hz", "ΔΓ of Savkoor contacts"),
    ),
)
