"""Every table contactres reads or writes: the one source of names, units and rules.

The readers and validators of the input tables, the writers of the output tables, the README's
column tables and the documentation's data dictionary (:mod:`contactres.report.dictionary`)
are generated from, or checked against, the schemas here (:data:`SCHEMAS`):

* inputs (:mod:`.inputs`): :data:`SWEEP_TABLE`, :data:`SPECTRA_TABLE`, :data:`AFM_TABLE`,
  :data:`RUM_TABLE`, each column with its rules (:class:`Rule`: a callable check and its words),
  which one validator runs (:func:`check_cells`, :func:`check_value`) to give the one-line error
  naming file, line, column, value and rule;
* outputs of ``qcm analyze`` (:mod:`.results`): :data:`SWEEP_RESULTS` (``sweeps.csv``),
  :data:`LOAD_RESULTS` (``loads.csv``), :data:`GROUP_RESULTS` (``summary.json``) and
  :data:`RADIATION_RESULTS` (``radiation.csv``), :data:`CURVE_RESULTS` (``curves.csv``) and
  :data:`JKR_CURVE_RESULTS` (``jkr_curves.csv``) (:mod:`.outputs`);
* the other outputs (:mod:`.outputs`): :data:`SPECTRA_SWEEPS`, :data:`SPECTRA_FITS`,
  :data:`STIFFNESS_CSV`, :data:`AFM_INVERT_RESULTS`, :data:`RUM_INVERT_RESULTS`;
* the tables of the forward computations and listings (:mod:`.listings`): :data:`CONTACT_TABLE`,
  :data:`DCSF_TABLE`, :data:`QCM_LOOP_TABLE`, :data:`CRYSTAL_TABLE`, :data:`CRYSTALS_LISTING`,
  :data:`EXAMPLES_LISTING`, :data:`PAPER1_RANKING`, :data:`PAPER2_LOOPS`, :data:`PAPER2_TURNING`,
  :data:`PAPER2_SHIFTS`;
* the tables of ``qcm particles`` (:mod:`._particles`): :data:`QCMD_SHIFTS_TABLE` (the tidy
  input), :data:`PARTICLES_CSV` and :data:`PARTICLE_SHIFTS_CSV`.

Every table of every job's Result (:mod:`contactres.jobs`) is bound to one of these.

The module sits in the measurements layer (its rules name the cells of a table with
:mod:`contactres.measurements._messages`), below analysis and report, which import it.
"""

from __future__ import annotations

from ._columns import (
    LEVELS,
    Column,
    Rule,
    TableSchema,
    broken_rule,
    check_cells,
    check_value,
    rule,
)
from ._inputs import (
    A_NUMBER,
    AFM_TABLE,
    FALSE_WORDS,
    FINITE,
    LARGEST_COUNT,
    NOT_EMPTY,
    NUMBER_TEXT,
    RUM_TABLE,
    SPECTRA_TABLE,
    SWEEP_TABLE,
    TRUE_WORDS,
    interval,
    plausible,
    stripped,
)
from ._listings import (
    CONTACT_TABLE,
    CRYSTAL_TABLE,
    CRYSTALS_LISTING,
    DCSF_TABLE,
    EXAMPLES_LISTING,
    PAPER1_RANKING,
    PAPER2_LOOPS,
    PAPER2_SHIFTS,
    PAPER2_TURNING,
    QCM_LOOP_TABLE,
)
from ._outputs import (
    AFM_INVERT_RESULTS,
    CURVE_RESULTS,
    JKR_CURVE_RESULTS,
    RADIATION_RESULTS,
    RUM_INVERT_RESULTS,
    SPECTRA_FITS,
    SPECTRA_SWEEPS,
    STIFFNESS_CSV,
)
from ._particles import PARTICLE_SHIFTS_CSV, PARTICLES_CSV, QCMD_SHIFTS_TABLE
from ._results import (
    COATING_CONVENTIONS,
    CONVENTIONS,
    GROUP_RESULTS,
    LOAD_QUANTITIES,
    LOAD_RESULTS,
    SWEEP_RESULTS,
)

__all__ = [
    "AFM_INVERT_RESULTS",
    "AFM_TABLE",
    "A_NUMBER",
    "COATING_CONVENTIONS",
    "CONTACT_TABLE",
    "CONVENTIONS",
    "CRYSTALS_LISTING",
    "CRYSTAL_TABLE",
    "CURVE_RESULTS",
    "DCSF_TABLE",
    "EXAMPLES_LISTING",
    "FALSE_WORDS",
    "FINITE",
    "GROUP_RESULTS",
    "INPUTS",
    "JKR_CURVE_RESULTS",
    "LARGEST_COUNT",
    "LEVELS",
    "LOAD_QUANTITIES",
    "LOAD_RESULTS",
    "NOT_EMPTY",
    "NUMBER_TEXT",
    "OUTPUTS",
    "PAPER1_RANKING",
    "PAPER2_LOOPS",
    "PAPER2_SHIFTS",
    "PAPER2_TURNING",
    "PARTICLES_CSV",
    "PARTICLE_SHIFTS_CSV",
    "QCMD_SHIFTS_TABLE",
    "QCM_LOOP_TABLE",
    "RADIATION_RESULTS",
    "RUM_INVERT_RESULTS",
    "RUM_TABLE",
    "SCHEMAS",
    "SPECTRA_FITS",
    "SPECTRA_SWEEPS",
    "SPECTRA_TABLE",
    "STIFFNESS_CSV",
    "SWEEP_RESULTS",
    "SWEEP_TABLE",
    "TRUE_WORDS",
    "Column",
    "Rule",
    "TableSchema",
    "broken_rule",
    "check_cells",
    "check_value",
    "interval",
    "plausible",
    "rule",
    "stripped",
]

#: The tables contactres reads (their columns carry the rules the readers run).
INPUTS: tuple[TableSchema, ...] = (
    SWEEP_TABLE,
    SPECTRA_TABLE,
    AFM_TABLE,
    RUM_TABLE,
    QCMD_SHIFTS_TABLE,
)
#: The tables contactres writes.
OUTPUTS: tuple[TableSchema, ...] = (
    SWEEP_RESULTS,
    LOAD_RESULTS,
    GROUP_RESULTS,
    RADIATION_RESULTS,
    CURVE_RESULTS,
    JKR_CURVE_RESULTS,
    SPECTRA_SWEEPS,
    SPECTRA_FITS,
    STIFFNESS_CSV,
    PARTICLES_CSV,
    PARTICLE_SHIFTS_CSV,
    AFM_INVERT_RESULTS,
    RUM_INVERT_RESULTS,
    CONTACT_TABLE,
    DCSF_TABLE,
    QCM_LOOP_TABLE,
    CRYSTAL_TABLE,
    CRYSTALS_LISTING,
    EXAMPLES_LISTING,
    PAPER1_RANKING,
    PAPER2_LOOPS,
    PAPER2_TURNING,
    PAPER2_SHIFTS,
)
#: Every schema, inputs first.
SCHEMAS: tuple[TableSchema, ...] = INPUTS + OUTPUTS
