"""The tables contactres reads, with the rules their readers run.

* :data:`SWEEP_TABLE`: the amplitude-sweep table (``qcm analyze``), one row per point of a ramp;
* :data:`SPECTRA_TABLE`: admittance spectra (``qcm spectra``), one row per frequency point;
* :data:`AFM_TABLE`, :data:`RUM_TABLE`: contact-resonance AFM and resonance ultrasound
  microscope tables (``afm invert``, ``rum invert``), one row per point or pixel.

Each rule (:class:`~.columns.Rule`) is the check and its words: the dictionary shows ``text``,
the reader's error ends with ``message``. A rule the readers of a kind of column all run (a
finite number, a non-empty label) is not shown (``shown=False``); the dictionary's empty rule
cell says it.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...numerics import column_run_starts
from ...units import MAX_AMPLITUDE_M, MIN_AMPLITUDE_M, POISSON_OPEN_RANGE, QUANTITIES, unit_slip
from .._cell_text import stripped_text_codes, text_cells
from ._columns import Column, Rule, TableSchema, rule

__all__ = [
    "AFM_TABLE",
    "A_NUMBER",
    "FALSE_WORDS",
    "FINITE",
    "LARGEST_COUNT",
    "NOT_EMPTY",
    "NUMBER_TEXT",
    "RUM_TABLE",
    "SPECTRA_TABLE",
    "SWEEP_TABLE",
    "TRUE_WORDS",
    "interval",
    "plausible",
    "stripped",
]

#: Largest count (overtone, n_contacts) taken: above 2**53 a float no longer holds every whole
#: number, and the integer columns of the table would overflow soon after.
LARGEST_COUNT = 2**53


def stripped(cells) -> np.ndarray:
    """The cells as text without the white space around them: what
    ``Series(cells).astype(str).str.strip().to_numpy()`` gives (an object array, NaN where a
    cell is missing), with each distinct cell stripped once. A sweep table of 10^6 rows holds
    10^5 sweep ids and a few labels: Python's strip per cell was 16 % of ``qcm analyze``
    (issue 31); factorising the cells is a hash table in C. Cells that are mostly distinct
    (more runs of equal cells than half the cells: a rule checked on the distinct sweep ids)
    are stripped one by one instead, as hashing them first would not spare a strip."""
    text = text_cells(cells)
    starts = column_run_starts(text)
    if starts is not None and 2 * len(starts) > len(text):
        return text.str.strip().to_numpy(dtype=object)
    codes, distinct, _ = stripped_text_codes(text, starts)  # (the runs found once)
    return distinct[codes]


def _filled(v: np.ndarray) -> np.ndarray:
    # pandas strings, not a numpy unicode array: that would be as wide as the longest label
    return stripped(v) != ""


def _number_text(v: np.ndarray) -> np.ndarray:
    """Cells (stripped, decimal point) that read as a number, or are blank or NaN."""
    import pandas as pd

    s = pd.Series(v, dtype=object).astype(str)
    number = pd.to_numeric(s, errors="coerce").notna()
    return (number | (s == "") | (s.str.lower() == "nan")).to_numpy()


def _whole(v: np.ndarray) -> np.ndarray:
    return (v == np.round(v)) & (v >= 1)


def _odd(v: np.ndarray) -> np.ndarray:
    return (v >= 1) & (v % 2 == 1)


#: Every number of a sweep table: finite (the error of the sweep table's reader).
FINITE = rule("finite", np.isfinite, "finite", " is not finite (NaN or infinite)")
#: The same, unsaid in the dictionary: any measured number is finite.
A_NUMBER = replace(FINITE, shown=False)
#: A label that must not be blank.
NOT_EMPTY = rule("not empty", _filled, "not empty", " is empty", shown=False)
#: A cell of a spectra table that reads as a number (blank or NaN: not given).
NUMBER_TEXT = rule("number", _number_text, "a number", " is not a number", shown=False)


#: The words of a true/false cell (lower case; blank is false).
TRUE_WORDS = frozenset({"true", "1", "yes", "y", "t"})
FALSE_WORDS = frozenset({"false", "0", "no", "n", "f", ""})


def _one_of(words):
    def accepts(v):
        import pandas as pd

        return pd.Series(v, dtype=object).astype(str).str.strip().str.lower().isin(words)

    return accepts


def _positive(message: str) -> Rule:
    return rule("positive", lambda v: v > 0, "> 0", message)


#: A count no larger than :data:`LARGEST_COUNT` (checked before the other rules of a count).
_COUNT = rule(
    "count",
    lambda v: np.abs(v) <= LARGEST_COUNT,
    "a count",
    " is too large to be a count",
    shown=False,
)


# --------------------------------------------------------------------------------------------
# The sweep table


def plausible(quantity: str, name: str | None = None) -> Rule:
    """The rule "a plausible value of ``quantity``" (:data:`contactres.units.QUANTITIES`), its
    error naming the unit slip the value looks like (nm typed for m, ...). ``name`` replaces the
    quantity's name in the message where a column holds another quantity of the same range
    (a lever's spring constant checked with the contact stiffness's range)."""
    plain = QUANTITIES[quantity]
    text = (plain if name is None else replace(plain, name=name)).describe()

    def hint(value) -> str:
        slip = unit_slip(quantity, value)
        return f"; it looks like {slip}" if slip else ""

    return rule(
        quantity,
        lambda v: np.asarray(QUANTITIES[quantity].accepts(v), dtype=bool),
        text,
        f": {text}",
        hint=hint,
    )


# The constants of a sweep table are checked as their command-line options are: positive and
# plausible (a sphere radius in mm in a metre column gave E = 2 GPa, issue 27).
_SWEEP_CONSTANT = {
    name: (_positive(f" must be > 0 ({unit})"), plausible(quantity))
    for name, unit, quantity in (
        ("fundamental_Hz", "Hz", "frequency"),
        ("area_m2", "m^2", "area"),
        ("sphere_radius_m", "m", "qcm_sphere_radius"),
    )
}

SWEEP_TABLE = TableSchema(
    "sweep table",
    "one row per measured point of an amplitude ramp (CSV: comma, semicolon or tab separated)",
    (
        Column(
            "sweep",
            "text",
            "id of one amplitude ramp",
            required=True,
            level="sweep",
            rules=(
                rule(
                    "not empty", _filled, "", " is empty; every row needs a sweep id", shown=False
                ),
            ),
        ),
        Column(
            "amplitude_m",
            "m",
            "oscillation amplitude u0",
            required=True,
            rules=(
                A_NUMBER,
                rule(
                    "non-negative",
                    lambda v: v >= 0,
                    ">= 0",
                    " is negative; amplitudes must be >= 0 m",
                ),
                rule(
                    "0 or at least 0.1 pm",
                    lambda v: (v == 0) | (v >= MIN_AMPLITUDE_M),
                    f"0 or >= {MIN_AMPLITUDE_M:g}",
                    f" is below {MIN_AMPLITUDE_M:g} m (and not 0), less than any QCM resolves: "
                    "check the column's unit (nm values go in amplitude_nm, metres in "
                    "amplitude_m)",
                ),
                rule(
                    "at most 1 µm",
                    lambda v: v <= MAX_AMPLITUDE_M,
                    f"<= {MAX_AMPLITUDE_M:g}",
                    f" is above {MAX_AMPLITUDE_M:g} m, more than any QCM amplitude: check the "
                    "column's unit (nm values go in amplitude_nm, metres in amplitude_m)",
                ),
            ),
        ),
        Column(
            "df_Hz",
            "Hz",
            "frequency shift Δf against the reference (no contact)",
            required=True,
            rules=(A_NUMBER,),
        ),
        Column(
            "dgamma_Hz",
            "Hz",
            "shift of the half-bandwidth ΔΓ at half height",
            required=True,
            rules=(A_NUMBER,),
        ),
        Column(
            "time_s",
            "s",
            "time of the point (any origin): lets a linear drift be removed (--remove-drift)",
            rules=(FINITE,),
        ),
        Column(
            "normal_force_N",
            "N",
            "normal force per contact",
            required=True,
            level="sweep",
            rules=(
                A_NUMBER,
                _positive(" is not positive; the normal force per contact must be > 0 N"),
            ),
        ),
        Column(
            "experiment",
            "text",
            "one mounting of the sample (repeats are experiments)",
            level="sweep",
            rules=(NOT_EMPTY,),
            default="1",
        ),
        Column(
            "configuration",
            "text",
            'groups with one material and geometry, e.g. "SiO2_2.2mm"',
            level="sweep",
            rules=(NOT_EMPTY,),
            default="default",
        ),
        Column(
            "medium",
            "text",
            '"air", "water", ...',
            level="sweep",
            rules=(NOT_EMPTY,),
            default="unspecified",
        ),
        Column(
            "ramp",
            "-",
            "1, 2, ...: order of the ramps of one load (ramp 1 is running-in)",
            level="sweep",
            rules=(A_NUMBER, rule("whole", _whole, "integer >= 1", " is not a positive integer")),
        ),
        Column(
            "fundamental_Hz",
            "Hz",
            "fundamental frequency f_F of the resonator",
            level="constant",
            rules=_SWEEP_CONSTANT["fundamental_Hz"],
            default=5e6,
        ),
        Column(
            "overtone",
            "-",
            "overtone order n",
            level="constant",
            rules=(
                _COUNT,
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
            "area_m2",
            "m^2",
            "acoustically effective area A_eff",
            level="constant",
            rules=_SWEEP_CONSTANT["area_m2"],
        ),
        Column(
            "n_contacts",
            "-",
            "number of equal contacts (3 for a tripod)",
            level="constant",
            rules=(
                _COUNT,
                rule("whole", _whole, "integer >= 1", " must be a positive integer"),
            ),
        ),
        Column(
            "sphere_radius_m",
            "m",
            "sphere radius R",
            level="constant",
            rules=_SWEEP_CONSTANT["sphere_radius_m"],
        ),
        Column(
            "poisson",
            "-",
            "Poisson ratio ν, fixed in the JKR + Mindlin fit",
            level="constant",
            rules=(
                rule(
                    "open range",
                    lambda v: (v > POISSON_OPEN_RANGE[0]) & (v < POISSON_OPEN_RANGE[1]),
                    "in ({:g}, {:g})".format(*POISSON_OPEN_RANGE),
                    " is outside ({:g}, {:g})".format(*POISSON_OPEN_RANGE),
                ),
            ),
            default=0.17,
        ),
    ),
)

# --------------------------------------------------------------------------------------------
# The spectra table (its label rules are checked on the values given, one per spectrum)

SPECTRA_TABLE = TableSchema(
    "spectra table",
    "one row per frequency point of an admittance spectrum (CSV, as the sweep table)",
    (
        Column(
            "spectrum",
            "text",
            "id of one spectrum (one amplitude step)",
            required=True,
            rules=(rule("not empty", _filled, "", " is empty; every row needs one", shown=False),),
        ),
        Column(
            "frequency_Hz",
            "Hz",
            "frequency of the point",
            required=True,
            rules=(
                rule("finite", np.isfinite, "finite", ": must be a finite number", shown=False),
                rule("positive", lambda v: v > 0, "> 0", ": must be > 0 Hz"),
            ),
        ),
        Column(
            "G_S",
            "S",
            "conductance Re Y (a NaN leaves its spectrum out, flagged)",
            required=True,
            rules=(NUMBER_TEXT,),
        ),
        Column(
            "B_S",
            "S",
            "susceptance Im Y (empty or absent: G alone is fitted)",
            rules=(NUMBER_TEXT,),
        ),
        Column(
            "reference",
            "-",
            "true for a no-contact reference spectrum (true/false, 1/0, yes/no)",
            level="sweep",
            rules=(
                rule(
                    "one of",
                    _one_of(TRUE_WORDS | FALSE_WORDS),
                    "true/false, 1/0, yes/no",
                    " is not true/false (or 1/0, yes/no)",
                    shown=False,  # the meaning says it
                ),
            ),
            default="false",
        ),
        Column(
            "overtone",
            "-",
            "overtone order n",
            level="sweep",
            rules=(
                rule("odd", _odd, "odd integer >= 1", ": the overtone must be an odd integer >= 1"),
            ),
        ),
        Column(
            "drive_voltage_V",
            "V",
            "amplitude (peak) of the drive voltage across the crystal",
            level="sweep",
            rules=(_positive(": must be > 0"),),
        ),
        Column(
            "time_s",
            "s",
            "time of the spectrum (any origin)",
            level="sweep",
            rules=(rule("finite", np.isfinite, "finite", ": must be finite"),),
        ),
        Column(
            "sweep", "text", "amplitude ramp of the spectrum (empty: a reference)", level="sweep"
        ),
        Column(
            "ramp",
            "-",
            "ramp number of the sweep",
            level="sweep",
            rules=(rule("whole", _whole, "integer >= 1", ": the ramp must be an integer >= 1"),),
        ),
        Column("experiment", "text", "experiment of the sweep", level="sweep", default="1"),
        Column(
            "normal_force_N",
            "N",
            "normal force per contact",
            level="sweep",
            rules=(_positive(": must be > 0"),),
        ),
        Column("configuration", "text", "configuration", level="sweep", default="default"),
        Column("medium", "text", "medium", level="sweep", default="unspecified"),
    ),
)

# --------------------------------------------------------------------------------------------
# Tables of measured resonances: CR-AFM and the resonance ultrasound microscope


def interval(
    unit: str,
    lo: float = -np.inf,
    hi: float = np.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
) -> Rule:
    """The rule "in [lo, hi]" (``lo_open``/``hi_open``: the bound excluded), in words with the
    column's ``unit``."""
    lo_text = f"{'(' if lo_open else '['}{lo:g}"
    hi_text = f"{hi:g}{')' if hi_open or np.isinf(hi) else ']'}"
    text = f"must lie in {lo_text}, {hi_text}{' ' + unit if unit not in ('-', '') else ''}"

    def check(v: np.ndarray) -> np.ndarray:
        above = v > lo if lo_open else v >= lo
        below = v < hi if hi_open else v <= hi
        return above & below

    return rule("interval", check, text, f": {text}")


_FREQ = plausible("frequency")
_Q = interval("-", 0.5, lo_open=True)  # below Q = 1/2 a resonance is overdamped: no peak to see
_MODES = (1, 2, 3)


def _col(name, unit, meaning, r: Rule, required=False) -> Column:
    return Column(name, unit, meaning, required=required, rules=(r,))


#: The contact-resonance AFM table (``contactres afm invert``).
AFM_TABLE = TableSchema(
    "afm-table",
    "one row per point or pixel: resonances of the free and the coupled lever",
    (
        *(
            _col(f"f{n}_free_Hz", "Hz", f"free-lever resonance of mode {n}", _FREQ, n == 1)
            for n in _MODES
        ),
        *(_col(f"Q{n}_free", "-", f"quality factor of free mode {n}", _Q) for n in _MODES),
        _col(
            "k_c_N_per_m",
            "N/m",
            "static spring constant at the free end, 3EI/L³",
            # The contact stiffness's wide range, not a lever's (<= 1e3 N/m): a RUM-like probe
            # of 1e6 N/m goes through this table too.
            plausible("stiffness", "spring constant of the lever"),
        ),
        _col(
            "tip_position",
            "-",
            "r = L1/L of the tip (blank: solved from two modes)",
            interval("-", 0.0, 1.0, lo_open=True),
        ),
        *(_col(f"fc{n}_Hz", "Hz", f"contact resonance of mode {n}", _FREQ) for n in _MODES),
        *(_col(f"Q{n}", "-", f"quality factor of contact mode {n}", _Q) for n in _MODES),
        _col("lateral_ratio", "-", "lateral spring k_lat/k*", interval("-", 0.0, 100.0)),
        _col("tip_height_over_L", "-", "tip height h/L", interval("-", 0.0, 1.0)),
        _col(
            "tilt_deg",
            "deg",
            "tilt of the lever from the sample's surface, > 0 with the free end nearer it",
            interval("deg", 0.0, 60.0),
        ),
        _col("tip_radius_m", "m", "tip radius R (Hertz)", plausible("sphere_radius")),
        _col("load_N", "N", "normal load P (Hertz)", plausible("force")),
        _col("M_tip_Pa", "Pa", "indentation modulus of the tip", plausible("modulus")),
        _col(
            "hardness_Pa",
            "Pa",
            "hardness of the sample (plasticity check)",
            plausible("modulus"),
        ),
        _col("fc1_ref_Hz", "Hz", "contact resonance (mode 1) on reference sample 1", _FREQ),
        _col("M_ref_Pa", "Pa", "indentation modulus of reference sample 1", plausible("modulus")),
        _col("fc1_ref2_Hz", "Hz", "contact resonance (mode 1) on reference sample 2", _FREQ),
        _col("M_ref2_Pa", "Pa", "indentation modulus of reference sample 2", plausible("modulus")),
    ),
)

#: The resonance ultrasound microscope table (``contactres rum invert``).
RUM_TABLE = TableSchema(
    "rum-table",
    "one row per point or pixel: free and contact resonance of the oscillator",
    (
        _col("f0_Hz", "Hz", "free resonance of the oscillator", _FREQ, required=True),
        _col("fc_Hz", "Hz", "contact resonance", _FREQ, required=True),
        _col(
            "K_eff_N_per_m",
            "N/m",
            "effective stiffness (lumped model)",
            plausible("stiffness", "effective stiffness of the oscillator"),
        ),
        _col("mass_kg", "kg", "mass of the rod (rod model)", interval("kg", 0.0, lo_open=True)),
    ),
)
