"""The data dictionary: the columns of the tables contactres reads or writes, and the flags.

Generated from :mod:`contactres.measurements.schema`, :mod:`contactres.analysis.flags` and (for
``radiation.csv``) ``contactres.analysis.radiation.RADIATION_RESULTS``; the
README's blocks between ``<!-- dictionary:NAME -->`` and ``<!-- /dictionary -->`` are these
tables (``python scripts/update_readme.py`` rewrites them; a test fails when they differ).

The outputs that have no schema object in the package (``fits.csv`` of ``qcm spectra``,
``stiffness.csv`` of ``qcm stiffness``, the columns ``afm invert`` and ``rum invert`` append)
are described here; their column names, units and flag names are checked against the code by
``tests/report/test_dictionary.py``. Their tables are on the documentation's data dictionary
page only (:data:`DOCS_ONLY`), not in README blocks.
"""

from __future__ import annotations

import re

from ..analysis.flags import DESCRIPTIONS, Flag
from ..analysis.inversion import FLAG_DESCRIPTIONS as MODULUS_FLAG_DESCRIPTIONS
from ..analysis.radiation import RADIATION_RESULTS
from ..measurements.resonances import AFM_TABLE, RUM_TABLE
from ..measurements.schema import (
    GROUP_RESULTS,
    LOAD_RESULTS,
    SWEEP_RESULTS,
    SWEEP_TABLE,
    Column,
    TableSchema,
)
from ..measurements.spectra import FLAGS as SPECTRA_FIT_FLAGS
from ..measurements.spectra_table import SPECTRA_TABLE

__all__ = [
    "AFM_INVERT_RESULTS",
    "BLOCK",
    "DOCS_ONLY",
    "RESONANCE_FLAGS",
    "RUM_INVERT_RESULTS",
    "SPECTRA_FITS",
    "STIFFNESS_CSV",
    "dictionary_tables",
    "flags_markdown",
    "update_blocks",
]

#: ``fits.csv`` of ``contactres qcm spectra --fits``: the columns of
#: :func:`contactres.measurements.spectra.fit_resonances`, in its order.
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
    ),
)

#: The columns ``contactres rum invert`` appends to the input's (which it copies).
RUM_INVERT_RESULTS = TableSchema(
    "rum invert output",
    "the input columns, then these",
    (
        Column("rum_model", "text", "lumped (K_eff_N_per_m given) or rod (mass_kg given)"),
        Column("k_star_N_per_m", "N/m", "contact stiffness k* from the contact resonance"),
    ),
)

#: The resonance flags of ``afm invert``: the names of
#: :func:`contactres.resonators.cantilever_inversion.flag_names`, written with hyphens.
RESONANCE_FLAGS = {
    "not-positive": "κ is <= 0, NaN or infinite",
    "below-free": "f below the mode's free frequency: only a negative κ reproduces it",
    "above-pinned": "f at or above the κ → ∞ limit of the mode for this tip position (κ NaN)",
    "insensitive": "d ln f / d ln κ < 1e-3: tip near a node of the mode, κ saturated, or κ → 0",
    "no-crossing": "two modes: no crossing κ_a(r) = κ_b(r) with r in [0.5, 1]",
    "several-crossings": "two modes: more than one crossing in [0.5, 1] (the largest r taken)",
    "not-measured": "a frequency is NaN (not measured)",
    "inconsistent-modes": "the modes disagree on κ by more than `--mode-tolerance`",
}

#: Tables on the documentation's dictionary page that have no README block.
DOCS_ONLY = (
    "spectra-fits",
    "spectra-fit-flags",
    "stiffness-csv",
    "afm-invert",
    "rum-invert",
    "resonance-flags",
)


def _flag_table(rows) -> str:
    lines = ["| flag | meaning |", "|---|---|"]
    lines += [f"| `{name}` | {text} |" for name, text in rows]
    return "\n".join(lines)


#: A README block: its name, its body and the end marker.
BLOCK = re.compile(
    r"(<!-- dictionary:(?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /dictionary -->)", re.S
)


def flags_markdown() -> str:
    """The flags of ``sweeps.csv`` and what each means, as a Markdown table."""
    lines = ["| flag | meaning |", "|---|---|"]
    lines += [f"| `{flag.text}` | {DESCRIPTIONS[flag]} |" for flag in Flag]
    return "\n".join(lines)


def dictionary_tables() -> dict[str, str]:
    """Block name -> Markdown table: the README's blocks and the :data:`DOCS_ONLY` tables."""
    return {
        "sweep-table": SWEEP_TABLE.markdown(with_required=True),
        "sweeps-csv": SWEEP_RESULTS.markdown(),
        "loads-csv": LOAD_RESULTS.markdown(),
        "summary-json": GROUP_RESULTS.markdown(),
        "radiation-csv": RADIATION_RESULTS.markdown(),
        "spectra-table": SPECTRA_TABLE.markdown(with_required=True),
        "flags": flags_markdown(),
        "afm-table": AFM_TABLE.markdown(with_required=True),
        "rum-table": RUM_TABLE.markdown(with_required=True),
        "spectra-fits": SPECTRA_FITS.markdown(),
        "spectra-fit-flags": _flag_table(SPECTRA_FIT_FLAGS.items()),
        "stiffness-csv": STIFFNESS_CSV.markdown(),
        "afm-invert": AFM_INVERT_RESULTS.markdown(),
        "rum-invert": RUM_INVERT_RESULTS.markdown(),
        "resonance-flags": _flag_table(
            [
                *RESONANCE_FLAGS.items(),
                *(
                    (str(f.name).lower().replace("_", "-"), t)
                    for f, t in MODULUS_FLAG_DESCRIPTIONS.items()
                ),
            ]
        ),
    }


def update_blocks(text: str) -> str:
    """``text`` with the body of every dictionary block replaced by the current table.

    Raises KeyError for a block whose name is not one of :func:`dictionary_tables`.
    """
    tables = dictionary_tables()

    def body(m: re.Match) -> str:
        return f"{m.group(1)}{tables[m.group('name')]}\n{m.group(4)}"

    return BLOCK.sub(body, text)
