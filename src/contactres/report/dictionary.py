"""The data dictionary: the columns of the tables contactres reads or writes, and the flags.

Generated from :mod:`contactres.measurements.schema` (every table: inputs with their rules,
outputs), :mod:`contactres.analysis` and the flags of the spectra fits and the inversions;
the README's blocks between ``<!-- dictionary:NAME -->`` and ``<!-- /dictionary -->`` are these
tables (``python scripts/update_readme.py`` rewrites them; a test fails when they differ).

The outputs of the other commands (the sweep table and ``fits.csv`` of ``qcm spectra``,
``stiffness.csv`` of ``qcm stiffness``, the tidy shift table and the two tables of ``qcm
particles``, the columns ``afm invert`` and ``rum invert`` append,
the listings of ``contact``, ``dcsf``, ``qcm loop`` and ``crystals``, the CSV of ``figures`` and
``demo``) have their schemas in :mod:`contactres.measurements.schema` too, the schemas the jobs
bind their tables to (:mod:`contactres.jobs`); ``tests/report/test_dictionary.py`` and
``tests/jobs/test_job_schemas.py`` compare their column names and the flag names with the code
that writes them. Their tables are on the documentation's data dictionary page only
(:data:`DOCS_ONLY`), not in README blocks.
"""

from __future__ import annotations

import re

from ..analysis import DESCRIPTIONS, PARTICLE_FLAGS, Flag
from ..analysis import FLAG_DESCRIPTIONS as MODULUS_FLAG_DESCRIPTIONS
from ..measurements import FLAGS as SPECTRA_FIT_FLAGS
from ..measurements.schema import (
    AFM_INVERT_RESULTS,
    AFM_TABLE,
    CONTACT_TABLE,
    CRYSTAL_TABLE,
    CRYSTALS_LISTING,
    CURVE_RESULTS,
    DCSF_TABLE,
    GROUP_RESULTS,
    JKR_CURVE_RESULTS,
    LOAD_RESULTS,
    PAPER1_RANKING,
    PAPER2_LOOPS,
    PAPER2_SHIFTS,
    PARTICLE_SHIFTS_CSV,
    PARTICLES_CSV,
    QCM_LOOP_TABLE,
    QCMD_SHIFTS_TABLE,
    RADIATION_RESULTS,
    RUM_INVERT_RESULTS,
    RUM_TABLE,
    SPECTRA_FITS,
    SPECTRA_SWEEPS,
    SPECTRA_TABLE,
    STIFFNESS_CSV,
    SWEEP_RESULTS,
    SWEEP_TABLE,
)

__all__ = [
    "AFM_INVERT_RESULTS",
    "BLOCK",
    "DOCS_ONLY",
    "RESONANCE_FLAGS",
    "RUM_INVERT_RESULTS",
    "SPECTRA_FITS",
    "STIFFNESS_CSV",
    "TABLE_FLAGS",
    "dictionary_tables",
    "flags_markdown",
    "update_blocks",
]

#: The resonance flags of ``afm invert``: the names of
#: :func:`contactres.resonators.flag_names`, written with hyphens.
RESONANCE_FLAGS = {
    "not-positive": "κ is <= 0, NaN or infinite",
    "below-free": "f below the mode's free frequency: only a negative κ reproduces it",
    "above-pinned": "f at or above the κ → ∞ limit of the mode for this tip position (κ NaN)",
    "insensitive": "d ln f / d ln κ < 1e-3: tip near a node of the mode, κ saturated, or κ → 0",
    "no-crossing": "two modes: no crossing κ_a(r) = κ_b(r) with r in [0.5, 1]",
    "several-crossings": (
        "two modes: more than one crossing in [0.5, 1] (information: the largest r taken, "
        "the next in tip_position_other, kappa_other)"
    ),
    "not-measured": "a frequency is NaN (not measured)",
    "inconsistent-modes": "the modes disagree on κ by more than `--mode-tolerance`",
    "no-contact": "f at the free frequency within 1e-6 of f either way: κ = 0 (no contact)",
}

#: Flags of the resonance tables' rows set from their input alone (after the inversion's and
#: the modulus step's): ``invert_afm_table`` in contactres.analysis.
TABLE_FLAGS = {
    "large-tip": (
        "tip_radius_m above 1 mm: check the unit (a CR-AFM tip is 1 nm-1 µm; a sphere of mm "
        "size is accepted, its values kept)"
    ),
}

#: Tables on the documentation's dictionary page that have no README block.
DOCS_ONLY = (
    "curves-csv",
    "jkr-curves-csv",
    "spectra-sweeps",
    "spectra-fits",
    "spectra-fit-flags",
    "stiffness-csv",
    "qcmd-shift-table",
    "particles-csv",
    "particle-shifts-csv",
    "particle-flags",
    "afm-invert",
    "rum-invert",
    "resonance-flags",
    "contact-listing",
    "dcsf-listing",
    "qcm-loop-listing",
    "crystals-listing",
    "crystals-csv",
    "paper1-ranking",
    "paper2-loops",
    "paper2-shifts",
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
        "curves-csv": CURVE_RESULTS.markdown(),
        "jkr-curves-csv": JKR_CURVE_RESULTS.markdown(),
        "spectra-table": SPECTRA_TABLE.markdown(with_required=True),
        "flags": flags_markdown(),
        "afm-table": AFM_TABLE.markdown(with_required=True),
        "rum-table": RUM_TABLE.markdown(with_required=True),
        "spectra-sweeps": SPECTRA_SWEEPS.markdown(),
        "spectra-fits": SPECTRA_FITS.markdown(),
        "spectra-fit-flags": _flag_table(SPECTRA_FIT_FLAGS.items()),
        "stiffness-csv": STIFFNESS_CSV.markdown(),
        "qcmd-shift-table": QCMD_SHIFTS_TABLE.markdown(with_required=True),
        "particles-csv": PARTICLES_CSV.markdown(),
        "particle-shifts-csv": PARTICLE_SHIFTS_CSV.markdown(),
        "particle-flags": _flag_table(PARTICLE_FLAGS.items()),
        "afm-invert": AFM_INVERT_RESULTS.markdown(),
        "rum-invert": RUM_INVERT_RESULTS.markdown(),
        "resonance-flags": _flag_table(
            [
                *RESONANCE_FLAGS.items(),
                *(
                    (str(f.name).lower().replace("_", "-"), t)
                    for f, t in MODULUS_FLAG_DESCRIPTIONS.items()
                ),
                *TABLE_FLAGS.items(),
            ]
        ),
        "contact-listing": CONTACT_TABLE.markdown(),
        "dcsf-listing": DCSF_TABLE.markdown(),
        "qcm-loop-listing": QCM_LOOP_TABLE.markdown(),
        "crystals-listing": CRYSTALS_LISTING.markdown(),
        "crystals-csv": CRYSTAL_TABLE.markdown(),
        "paper1-ranking": PAPER1_RANKING.markdown(),
        "paper2-loops": PAPER2_LOOPS.markdown(),
        "paper2-shifts": PAPER2_SHIFTS.markdown(),
    }


def update_blocks(text: str) -> str:
    """``text`` with the body of every dictionary block replaced by the current table.

    Raises KeyError for a block whose name is not one of :func:`dictionary_tables`.
    """
    tables = dictionary_tables()

    def body(m: re.Match) -> str:
        return f"{m.group(1)}{tables[m.group('name')]}\n{m.group(4)}"

    return BLOCK.sub(body, text)
