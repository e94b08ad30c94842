"""Amplitude-sweep tables (paper 2): reading and validating into a :class:`SweepTable`.

A sweep table has one row per measured point of an amplitude ramp; its columns, units and rules
are those of :data:`contactres.measurements.schema.SWEEP_TABLE` (the README lists them).
Conventions: Δf is the frequency shift (not Δf/n) and ΔΓ the shift of the half-bandwidth at half
height (Γ, not the dissipation factor D = 2Γ/f), both in Hz.

Constants missing from the table come, in this order, from keyword arguments of
:func:`read_sweeps` (the CLI options), from a TOML file beside the data (``<stem>.toml``, else
``contactres.toml`` in the same folder; keys as the column names) and, for ``fundamental_Hz``
(5 MHz) and ``poisson`` (0.17, as in paper 2) only, from documented defaults. A value in a row
overrides the others; an argument or a TOML value beside the column is still checked by the
column's rules, and a warning says so when it disagrees. A column whose name looks like a
misspelling of one the table lacks (``poison``) is an error, not a note.

Files are read by reader plug-ins (:mod:`contactres.measurements.readers`); every error names the
file, the line, the column and the value.
"""

from __future__ import annotations

import datetime
import math
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from .._column_names import repeated_names, repeats_text
from .._summary import Summarised, table_size
from ..errors import ContactresInputError
from ..numerics import factorize_runs, run_starts
from ..units import ABSOLUTE_FREQUENCY_FRACTION, SMALL_LOAD_LIMIT
from ._cell_text import stripped_codes
from ._checksum import hashed_load
from ._messages import at_cell, column_named, column_names, line_word, shown_value, where_rows
from ._sweep_checks import (
    SweepWarning,
    check_dissipation_sign,
    check_per_sweep,
    drop_duplicates,
    warn_sweeps,
)
from ._toml import toml_table
from ._unit_columns import bare_name, columns_in_si, si_unit
from .schema import FINITE, SWEEP_TABLE, broken_rule, check_cells, check_value, stripped

__all__ = [
    "CONSTANTS",
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "SweepTable",
    "SweepWarning",
    "read_sweeps",
    "validate_sweeps",
]

#: Columns every sweep table must have.
REQUIRED_COLUMNS = SWEEP_TABLE.required
#: Optional columns.
OPTIONAL_COLUMNS = SWEEP_TABLE.optional
#: Label columns and their defaults when absent.
LABEL_DEFAULTS = {
    c.name: c.default for c in SWEEP_TABLE.columns if c.unit == "text" and c.default is not None
}
#: Constants: name -> (unit, documented default or None when it must be supplied).
CONSTANTS: dict[str, tuple[str, float | None]] = {
    c.name: (c.unit, None if c.default is None else float(c.default))
    for c in SWEEP_TABLE.columns
    if c.level == "constant"
}
#: Columns that must take one value within a sweep.
PER_SWEEP_COLUMNS = tuple(
    c.name for c in SWEEP_TABLE.columns if c.level in ("sweep", "constant") and c.name != "sweep"
)
#: Columns of a validated table, in order.
VALIDATED_COLUMNS = (
    "sweep", "experiment", "configuration", "medium", "ramp", "normal_force_N", "amplitude_m",
    "df_Hz", "dgamma_Hz", *CONSTANTS, "time_s", "line",
)  # fmt: skip


# repr=False: the summary (Summarised, _facts) replaces the printout of the whole table.
@dataclass(frozen=True, repr=False)
class SweepTable(Summarised):
    """A validated sweep table: what :func:`contactres.analyze` takes.

    Attributes
    ----------
    data : one row per point, the columns of :data:`VALIDATED_COLUMNS` (every constant filled
        in; ``line`` is the line number of the row in the file)
    source : the file (or ``<table>`` for a table built in memory)
    source_sha256 : SHA-256 (hex) of the file's bytes, taken when it was read (None: a table
        built in memory, or read from a folder); the report shows it
    """

    data: pd.DataFrame
    source: str = "<table>"
    source_sha256: str | None = None

    def __post_init__(self):
        if not isinstance(self.data, pd.DataFrame) or list(self.data.columns) != list(
            VALIDATED_COLUMNS
        ):
            raise ContactresInputError(
                "a SweepTable holds a validated table: build it with read_sweeps() or "
                "validate_sweeps(frame, constants={...})"
            )

    def __len__(self) -> int:
        return len(self.data)

    def _facts(self) -> list[tuple[str, str]]:
        """The source, the numbers of sweeps and points, the columns and the file's hash."""
        facts = [("", repr(self.source)), ("sweeps", str(self.data["sweep"].nunique()))]
        facts.append(("points", table_size(self.data)))
        if self.source_sha256:
            facts.append(("sha256", self.source_sha256[:12] + "…"))
        return facts

    def with_constants(self, **values) -> SweepTable:
        """The same points with the constants ``values`` (keys of :data:`CONSTANTS`) in every
        row, validated again as a whole (as :func:`validate_sweeps` does)."""
        unknown = sorted(set(values) - set(CONSTANTS))
        if unknown:
            raise ContactresInputError(f"unknown constant(s) {unknown}; allowed: {list(CONSTANTS)}")
        given = {name: _check_constant(name, v, f"argument {name}") for name, v in values.items()}
        table = validate_sweeps(self.data.drop(columns=list(given)), self.source, constants=given)
        return replace(table, source_sha256=self.source_sha256)  # the same input file


# --------------------------------------------------------------------------------------------
# Constants


def _toml_constants(path: Path) -> tuple[dict, Path | None]:
    for candidate in (path.with_suffix(".toml"), path.parent / "contactres.toml"):
        if candidate.is_file():
            try:
                text = candidate.read_bytes().decode("utf-8")
            except UnicodeDecodeError as exc:
                raise ContactresInputError(
                    f"{candidate}: not UTF-8 text (offset {exc.start})"
                ) from None
            data = toml_table(text, candidate)
            data = _toml_keys_in_si(data, candidate)
            unknown = sorted(set(data) - set(CONSTANTS))
            if unknown:
                raise ContactresInputError(
                    f"{candidate}: unknown key(s) {column_names(unknown)}; "
                    f"allowed: {list(CONSTANTS)}, each also with its value's unit "
                    '(sphere_radius = "1.1 mm") or another unit in its name '
                    "(sphere_radius_mm = 1.1)"
                )
            return data, candidate
    return {}, None


def _toml_key_with_unit(key: str, value, bare: dict, path: Path) -> tuple[str, object]:
    """A TOML key named with another unit than the constant's (``sphere_radius_mm = 1.1``, as
    the column ``sphere_radius_mm``) as the constant's own key and its value in SI; any other
    key as it is."""
    if key in CONSTANTS or key in bare:
        return key, value
    for short, name in bare.items():
        if not key.startswith(short + "_"):
            continue
        from ..typed_units import column_unit_factor

        factor = column_unit_factor(key[len(short) + 1 :], si_unit(SWEEP_TABLE.column(name).unit))
        if factor is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ContactresInputError(
                f"{path}: {key} = {shown_value(value)}: a key named with its unit takes a plain "
                f'number (or write {short} = "1.1 mm", the value with its unit)'
            )
        return name, value * factor
    return key, value


def _toml_keys_in_si(data: dict, path: Path) -> dict:
    """A TOML file's keys with a constant's bare name (``sphere_radius = "1.1 mm"``: the value
    carries its unit) renamed to the constant (``sphere_radius_m``); both given is an error."""
    bare = {bare_name(name): name for name in CONSTANTS if bare_name(name) != name}
    out: dict = {}
    written_as: dict[str, str] = {}
    for written, value in data.items():
        key, value = _toml_key_with_unit(written, value, bare, path)
        name = bare.get(key, key)
        # The key as the file writes it, and the earlier one of the same constant (a key in
        # another unit was named by the constant's own name, which the file may not hold).
        other = written_as.get(name, name if name != key and name in data else None)
        if other is not None:
            raise ContactresInputError(
                f"{path}: {written} and {other} are the same constant; give one of them"
            )
        out[name], written_as[name] = value, written
    return out


def _check_constant(name: str, value, where: str, shown=None) -> float:
    """``value`` as a float if it passes the rule of ``name`` (``shown``: as written, if not it)."""
    if isinstance(value, (datetime.date, datetime.time)):  # TOML dates: as written, not a repr
        raise ContactresInputError(
            f"{where}: {name} = {value.isoformat()} is a date or time, not a number"
        )
    if isinstance(value, (list, dict)):
        what = "an array" if isinstance(value, list) else "a table"
        raise ContactresInputError(f"{where}: {name} is {what}, not a number")
    shown = shown_value(value if shown is None else shown)
    if isinstance(value, (bool, np.bool_)):  # TOML true/false: float() would make it 1/0
        raise ContactresInputError(
            f"{where}: {name} = {str(value).lower()} is a boolean, not a number"
        )
    try:
        v = float(value)
    except (TypeError, ValueError):
        from ..typed_units import has_unit, to_si

        if not has_unit(value):
            raise ContactresInputError(f"{where}: {name} = {shown} is not a number") from None
        # A value with its unit ("1.1 mm"): converted to the column's SI unit, then checked
        # by the same rules as a plain number (issue 30).
        v = to_si(value, si_unit(SWEEP_TABLE.column(name).unit), f"{where}: {name} =")
    if not math.isfinite(v):
        raise ContactresInputError(f"{where}: {name} = {shown} is not finite")
    check_value(name, v, where, shown, SWEEP_TABLE.column(name).rules)
    return v


# --------------------------------------------------------------------------------------------
# Reading


def read_sweeps(path, *, readers=None, **constants) -> SweepTable:
    """Read an amplitude-sweep table into a validated :class:`SweepTable`.

    Parameters
    ----------
    path : str or path-like
        The table (CSV: comma, semicolon or tab separated; decimal point, or decimal comma with
        semicolon or tab separators). Never modified.
    **constants
        Values for constants missing from the file: ``fundamental_Hz`` (Hz), ``overtone``,
        ``area_m2`` (m^2, acoustically effective area), ``n_contacts``, ``sphere_radius_m`` (m),
        ``poisson``. ``None`` means "not given".
    readers : Readers, optional
        The registry to pick the file's reader from (kind ``sweeps``; default
        :data:`~contactres.measurements.readers.BUILT_IN`). A reader of your own:
        ``readers=BUILT_IN.with_reader(Reader(name, suffixes, detect, load, "sweeps"))``.

    Returns
    -------
    SweepTable

    Raises
    ------
    ValueError
        On every bad input, naming file, line, column and value (see :func:`validate_sweeps`).

    Examples
    --------
    The example table shipped with the package:

    >>> from importlib.resources import files
    >>> from contactres import read_sweeps
    >>> table = read_sweeps(files("contactres") / "data" / "example_sweeps.csv")
    >>> len(table), table.data["sweep"].nunique()
    (4608, 384)
    """
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{p}: no such file")
    if p.is_dir():
        raise ContactresInputError(f"{p}: is a directory, expected a sweep table file")
    unknown = sorted(set(constants) - set(CONSTANTS))
    if unknown:
        raise ContactresInputError(f"unknown constant(s) {unknown}; allowed: {list(CONSTANTS)}")
    given = {k: v for k, v in constants.items() if v is not None}
    toml, toml_path = _toml_constants(p)
    # Imported here: the registry imports every reader (the instrument exports, the AFM files),
    # which a table validated in memory, e.g. by the analysis, never uses (issue 31).
    from .readers import BUILT_IN

    reader = (BUILT_IN if readers is None else readers).pick(p, "sweeps")
    raw, digest = hashed_load(reader, p, BUILT_IN)  # the hash of the bytes parsed
    # A workbook's reader names its sheet too ("book.xlsx, sheet 'sweeps'").
    source = str(raw.attrs.get("source", p))
    table = validate_sweeps(
        raw,
        source=source,
        constants=given,
        file_constants=toml,
        file_constants_source=str(toml_path) if toml_path else None,
    )
    return replace(table, source_sha256=digest)


# --------------------------------------------------------------------------------------------
# Validation


#: A column whose first this many cells hold at most a tenth as many distinct texts (a
#: constant, a load, a ramp) is read one distinct text at a time.
_SAMPLE = 1000


def _numbers(text: pd.Series, decimal: str) -> tuple[np.ndarray, np.ndarray]:
    """The numbers of the text cells ``text`` (NaN where none) and where a cell is not one."""
    # pandas' parser (C) skips the ASCII white space around a number: a cell it reads as
    # written reads the same stripped. Only the others (NaN so far: a decimal comma, other
    # white space, "nan", a word) are stripped and read again, cell by cell in Python.
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float, copy=True)
    again = np.flatnonzero(np.isnan(values))
    s = pd.Series(stripped(text.iloc[again]), dtype=object)
    if decimal == ",":
        s = s.str.replace(",", ".", regex=False)
    values[again] = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float)
    bad = np.zeros(len(values), bool)
    bad[again] = np.isnan(values[again]) & ~s.str.lower().isin(["nan"]).to_numpy()
    return values, bad


def _given_as_numbers(cells: pd.Series) -> bool:
    """Whether ``cells`` hold numbers already (float64 or integers, as a table built in memory
    has them): each is the number its text would give (Python writes a float64 as the shortest
    text that reads back to it; an integer exactly), so it is taken as it is. Float32 is not
    (its shortest text reads back as another float64), nor are booleans (not numbers here)."""
    dtype = cells.dtype
    return isinstance(dtype, np.dtype) and (dtype == np.float64 or dtype.kind in "iu")


def _numeric(raw: pd.DataFrame, col: str, source: str, decimal: str) -> np.ndarray:
    if col in raw.attrs.get("number_columns", ()) or _given_as_numbers(raw[col]):
        # Read as numbers by the reader (finite, each the number its text gives: the same
        # converter as below; readers/_delimited._parsed) or given as numbers: no text to read
        # again (writing 10^6 numbers as text to read them back cost ~7 s, issue 31). Not
        # copied here: the values are only read, and the frame they are set into copies them.
        values = raw[col].to_numpy(dtype=float)
        check_cells(raw, source, col, (FINITE,), values)
        return values
    text = raw[col].astype(str)
    if text.iloc[:_SAMPLE].nunique() * 10 <= min(len(text), _SAMPLE):
        # Few distinct cells: each text read once (the same parser, so the same number), the
        # rows given theirs by a hash table in C (issue 31: 10^6 rows of a constant), on the
        # first cell of each run of equal cells (a constant is one run, a ramp one a sweep).
        codes, distinct = factorize_runs(text, use_na_sentinel=False)
        numbers, broken = _numbers(pd.Series(distinct, dtype=object), decimal)
        values = numbers[codes]
        # (the rows' mask only where some distinct text is no number)
        bad = broken[codes] if broken.any() else np.zeros(len(codes), dtype=bool)
    else:
        values, bad = _numbers(text, decimal)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        shown = raw[col].iloc[i]
        what = (
            "is empty" if not str(shown).strip() else f"value {shown_value(shown)} is not a number"
        )
        raise ContactresInputError(f"{where_rows(raw, source, bad, col)}: {what}")
    check_cells(raw, source, col, (FINITE,), values)
    return values


def _labels(
    out: pd.DataFrame, raw: pd.DataFrame, source: str, col: str, missing: np.ndarray | None = None
) -> np.ndarray:
    """``out[col]``: the cells of ``raw[col]`` stripped (as :func:`stripped` gives them), the
    rules of the column checked; where ``missing`` (a mask) has a cell, as an empty one.
    Returns a code for each row, equal where the texts of ``out[col]`` are (what
    ``pandas.factorize(out[col])`` gives).

    Each distinct text is stripped and checked once (the rules are element-wise): 10^6 rows
    hold 10^5 sweep ids and a few labels, and the check stripped every cell again (issue 31).
    A broken rule is named by the check of every cell, as before. The codes serve the checks
    of the rows (duplicates, one value per sweep), which hashed the 10^6 texts again."""
    codes, distinct, exact = stripped_codes(raw[col])
    # The column pandas makes of ``distinct[codes]``, its type inferred from the distinct
    # texts and the rows then taken from them: inferring it from 10^6 objects, then checking
    # and copying each into pandas' text array, cost ~0.04 s a column (issue 31, point 3).
    out[col] = pd.Series(distinct).array.take(codes)
    rules = SWEEP_TABLE.column(col).rules
    if missing is not None and missing.any():
        SWEEP_TABLE.check_cells(out, source, col, np.where(missing, "", out[col].to_numpy()))
        return pd.factorize(out[col])[0]
    if broken_rule(rules, distinct) is not None:
        SWEEP_TABLE.check_cells(out, source, col)
    # Texts that differed by the white space around them are one text once stripped.
    return codes if exact else pd.factorize(distinct)[0][codes]


def _labels_and_numbers(
    raw: pd.DataFrame, source: str, decimal: str
) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
    """Sweep ids, label columns (or their defaults), the measured numbers and the ramp; and
    the codes of the sweep ids and labels (:func:`_labels`)."""
    out = pd.DataFrame({"line": raw["line"].to_numpy()})
    out.attrs["line_word"] = line_word(raw)  # a workbook's rows are named rows, not lines
    out.attrs["written_as"] = raw.attrs.get("written_as", {})  # amplitude_nm: amplitude_m
    # A missing cell of a table built in memory is empty too (its text would be "nan").
    missing = raw["sweep"].isna().to_numpy()
    codes = {"sweep": _labels(out, raw, source, "sweep", missing)}
    for col, default in LABEL_DEFAULTS.items():
        if col in raw.columns:
            codes[col] = _labels(out, raw, source, col)
        else:
            out[col] = default
            codes[col] = np.zeros(len(out), dtype=np.intp)
    for col in ("amplitude_m", "df_Hz", "dgamma_Hz", "normal_force_N"):
        out[col] = _numeric(raw, col, source, decimal)
    # Optional time of each point (NaN where the table has none).
    # (A column of NaN only, as a validated table carries when it had none, is no column.)
    if "time_s" in raw.attrs.get("number_columns", ()):
        blank = np.zeros(len(raw), dtype=bool)  # numbers, finite: none blank
    elif "time_s" in raw:
        cells = raw["time_s"]
        blank = (
            cells.isna() | cells.astype(str).str.strip().str.lower().isin(["", "nan"])
        ).to_numpy(dtype=bool)
    given = "time_s" in raw and not blank.all()
    out["time_s"] = _numeric(raw, "time_s", source, decimal) if given else np.nan
    if "ramp" in raw.columns:
        out["ramp"] = _numeric(raw, "ramp", source, decimal)
        SWEEP_TABLE.check_cells(out, source, "ramp")
        out["ramp"] = out["ramp"].to_numpy().astype(int)
    else:
        out["ramp"] = 0
        # The analysis orders by time only where every point has one (as this line says).
        timed = given and not blank.any()
        warnings.warn(
            f"{source}: no 'ramp' column: the ramps of each load are inferred as its sweeps "
            f"in the order of {'their times' if timed else 'the file'}, the first one taken as "
            "running-in (ramp reported as 0)",
            SweepWarning,
            stacklevel=3,
        )
    return out, codes


def _fill_constants(
    out: pd.DataFrame,
    raw: pd.DataFrame,
    source: str,
    decimal: str,
    constants: dict,
    file_constants: dict,
    file_constants_source: str | None,
) -> None:
    """Constants, in place: row value > argument > TOML beside the file > documented default.
    Where an argument or the TOML gave one is kept in ``out.attrs["constant_sources"]``, for
    the messages that blame it."""
    absent = []
    sources = out.attrs.setdefault("constant_sources", {})
    for name in CONSTANTS:
        if name in raw.columns:
            vals = _numeric(raw, name, source, decimal)
            out[name] = vals
            # Distinct values validated only (cheap), found among the first rows of the runs
            # of equal values: sorting every value cost ~0.02 s a column of 10^6 (issue 31).
            for v in np.unique(vals[run_starts(vals)]):
                i = int(np.flatnonzero(vals == v)[0])
                where = f"{source}, {line_word(out)} {out['line'].iloc[i]}, column "
                where += column_named(out, name)
                _check_constant(name, v, where, shown=raw[name].iloc[i])
            # A value the column overrides is still checked by the same rules (a TOML radius
            # in mm beside a metre column passed unseen, issue 27), and a different value is
            # said, with which one is used: the row's (the order of the module docstring).
            if name in constants:
                v = _check_constant(name, constants[name], f"argument {name}")
                if _differs(vals, v):
                    warnings.warn(
                        f"{source}: column {column_named(out, name)} overrides the given {name} = "
                        f"{shown_value(constants[name])}",
                        SweepWarning,
                        stacklevel=4,
                    )
            if name in file_constants:
                where = f"{file_constants_source}, key {name!r}"
                v = _check_constant(name, file_constants[name], where)
                if _differs(vals, v):
                    warnings.warn(
                        f"{where}: {name} = {shown_value(file_constants[name])} differs from "
                        f"column {column_named(out, name)} of {source} ({_column_values(vals)}); "
                        "the column's value is used",
                        SweepWarning,
                        stacklevel=4,
                    )
        elif name in constants:
            out[name] = _check_constant(name, constants[name], f"argument {name}")
            sources[name] = f"argument {name}"
        elif name in file_constants:
            where = f"{file_constants_source}, key {name!r}"
            out[name] = _check_constant(name, file_constants[name], where)
            sources[name] = where
        elif (default := CONSTANTS[name][1]) is not None:
            out[name] = default
        else:
            absent.append(f"{name} ({CONSTANTS[name][0]})")
    if absent:
        raise ContactresInputError(
            f"{source}: constant(s) missing: {', '.join(absent)}; give each as a column, as an "
            f"argument/CLI option, or in a TOML file beside the data "
            f"('{Path(source).with_suffix('.toml').name}', e.g. area_m2 = 2.5e-5)"
        )
    out["overtone"] = out["overtone"].astype(int)
    out["n_contacts"] = out["n_contacts"].astype(int)


def _differs(vals: np.ndarray, value: float) -> bool:
    """True if a column's values are not all ``value`` (a relative 1e-9 apart: "1.1 mm"
    converted to metres need not be the same float as 0.0011 typed)."""
    return bool(np.any(~np.isclose(vals, value, rtol=1e-9, atol=0.0)))


def _column_values(vals: np.ndarray) -> str:
    """The distinct values of a constant's column for a message: one, or the first and a count."""
    distinct = np.unique(vals)
    first = f"{distinct[0]:g}"
    return first if len(distinct) == 1 else f"{first}, ... {len(distinct)} values"


def _check_physics(out: pd.DataFrame, source: str) -> None:
    """Amplitudes, forces and shifts in their physical (and unit-plausible) ranges."""
    for col in ("amplitude_m", "normal_force_N"):
        SWEEP_TABLE.check_cells(out, source, col)
    f_res = out["fundamental_Hz"].to_numpy() * out["overtone"].to_numpy()
    for col in ("df_Hz", "dgamma_Hz"):
        v = np.abs(out[col].to_numpy())
        absolute = v > ABSOLUTE_FREQUENCY_FRACTION * out["fundamental_Hz"].to_numpy()
        if absolute.any():
            # Either side may be wrong: name the fundamental and where it came from (a TOML
            # fundamental_Hz = 5 was blamed on df_Hz alone, issue 27).
            f_f = float(out["fundamental_Hz"].to_numpy()[np.flatnonzero(absolute)[0]])
            given = out.attrs.get("constant_sources", {}).get("fundamental_Hz", "column")
            raise ContactresInputError(
                f"{at_cell(out, source, absolute, col)} is above {ABSOLUTE_FREQUENCY_FRACTION:g} "
                f"of the fundamental {f_f:g} Hz (fundamental_Hz, {given}): an absolute "
                "frequency, not a shift (subtract the reference frequency), or a wrong "
                "fundamental (a QCM's is 1 to 100 MHz)"
            )
        large = v > SMALL_LOAD_LIMIT * f_res
        if large.any():
            warnings.warn(
                f"{at_cell(out, source, large, col)} Hz is above {SMALL_LOAD_LIMIT:g} of the "
                "resonance frequency: the small-load approximation (paper 2, Eq. 1) may fail",
                SweepWarning,
                stacklevel=4,
            )


def validate_sweeps(
    raw: pd.DataFrame,
    source: str = "<table>",
    constants: dict | None = None,
    file_constants: dict | None = None,
    file_constants_source: str | None = None,
) -> SweepTable:
    """Validate a raw sweep table (strings or numbers) into a :class:`SweepTable`.

    ``raw`` may come from a reader (string cells, ``line`` column) or be built in memory (then
    rows are numbered as if a header were line 1). See :func:`read_sweeps` for the arguments.
    Errors (ValueError) for: no rows, a missing required or a duplicated column name,
    empty/non-numeric/NaN/infinite cells, negative amplitudes, amplitudes above 1 µm (nm in a
    metre column), an even overtone, a boolean or too large count, shifts that look like absolute
    frequencies, non-positive normal force, a constant that is missing or differs within one
    sweep, a sphere radius or Poisson ratio that differs within one configuration, a column
    named like a misspelling of one the table lacks. Warnings (:class:`SweepWarning`) for
    duplicated rows (dropped), sweeps with fewer than 4 points or all amplitudes equal, a
    missing ``ramp`` column, arguments or TOML values overridden by the file, and shifts that
    break the small-load approximation. Values in messages are cut to 60 characters.
    """
    word = line_word(raw)
    # A new frame over the same columns; a deep copy cost ~0.25 s at 10^6 rows (issue 31,
    # point 3). pandas 3 copies on write; pandas 2 (pyproject allows >= 2.0) does not by
    # default, so the caller's table stays as it was only because nothing below writes into a
    # column in place (columns are renamed, added or replaced whole).
    raw = raw.copy(deep=False)
    as_given = [str(c) for c in raw.columns]
    raw.columns = [c.strip() for c in as_given]
    # (a reader refuses a name twice in its header; a table built in memory may hold one, or
    # two names that differ by outer blanks only; two units of one quantity: columns_in_si)
    repeats = repeats_text(raw.columns)
    if repeats is not None:
        # "once stripped" only where stripping made the repeat (the names as given differ)
        stripped = repeated_names(raw.columns) != repeated_names(as_given)
        raise ContactresInputError(
            f"{source}: duplicate column name(s) {repeats}"
            f"{' once stripped of blanks' if stripped else ''}; one name each"
        )
    raw = columns_in_si(raw, source)
    raw.attrs["line_word"] = word
    # A misspelt column ("poison") would leave its value unused, the default in its place.
    SWEEP_TABLE.check_names(raw.columns, source)
    if "line" not in raw.columns:
        raw["line"] = np.arange(2, len(raw) + 2)
    decimal = raw.attrs.get("decimal", ".")
    comments = raw.attrs.get("comment_lines", ())
    if comments:
        # Imported here: the readers' package serves read_sweeps, not a table validated in memory.
        from .readers import line_ranges

        warnings.warn(
            f"{source}: {len(comments)} comment line(s) skipped (first character '#'): "
            f"line(s) {line_ranges(comments)}",
            SweepWarning,
            stacklevel=3,
        )
    # The names as the file spells them (amplitude_nm, not amplitude_m), for the messages
    data_cols = [raw.attrs.get("written_as", {}).get(c, c) for c in raw.columns if c != "line"]
    if len(raw) == 0:
        raise ContactresInputError(
            f"{source}: header only, no data rows; columns: {column_names(data_cols)}"
        )
    missing = [c for c in REQUIRED_COLUMNS if c not in raw.columns]
    if missing:
        raise ContactresInputError(
            f"{source}: missing required column(s) {missing}; "
            f"columns found: {column_names(data_cols)}; "
            f"required: {list(REQUIRED_COLUMNS)}, optional: {list(OPTIONAL_COLUMNS)}"
        )
    out, codes = _labels_and_numbers(raw, source, decimal)
    given, in_file = dict(constants or {}), dict(file_constants or {})
    _fill_constants(out, raw, source, decimal, given, in_file, file_constants_source)
    _check_physics(out, source)
    rows = len(out)
    out = drop_duplicates(out, source, codes["sweep"])
    if len(out) < rows:  # the codes are the full table's: the labels are hashed again
        codes = {}
    check_per_sweep(out, source, PER_SWEEP_COLUMNS, codes)
    check_dissipation_sign(out, source, codes.get("sweep"))
    warn_sweeps(out, source, codes.get("sweep"))
    return SweepTable(out[list(VALIDATED_COLUMNS)].reset_index(drop=True), source)
