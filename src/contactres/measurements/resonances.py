"""Tables of measured resonances: contact-resonance AFM and the resonance ultrasound microscope.

One row per point or map pixel; SI units, the unit in every column name; a blank cell means "not
given" (a mode that was not measured, a tip position to be solved from two modes). The schemas
(:data:`AFM_TABLE`, :data:`RUM_TABLE`) are the one source of the names, units and rules: the
reader checks against them and the README's column tables are generated from them. Columns that
are not in the schema are carried through to the output unchanged (point labels, pixel
coordinates), except a name that differs from a schema column only in case (``fc1_hz``): that
is taken for a typo and refused.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..units import QUANTITIES, unit_slip
from .messages import at_cell, shown_value, where_rows
from .readers import pick_reader
from .schema import Column, TableSchema

__all__ = ["AFM_TABLE", "RUM_TABLE", "Rule", "read_resonance_table", "validate_resonance_table"]


@dataclass(frozen=True)
class Rule:
    """The check of one numeric column: a plausible magnitude of :data:`contactres.units
    .QUANTITIES` (``quantity``) or a closed/open interval (``lo``, ``hi``) in words."""

    quantity: str = ""
    lo: float = -np.inf
    hi: float = np.inf
    lo_open: bool = False
    hi_open: bool = False

    def accepts(self, v: np.ndarray) -> np.ndarray:
        if self.quantity:
            return np.asarray(QUANTITIES[self.quantity].accepts(v), dtype=bool)
        above = v > self.lo if self.lo_open else v >= self.lo
        below = v < self.hi if self.hi_open else v <= self.hi
        return above & below

    def describe(self, unit: str) -> str:
        if self.quantity:
            return QUANTITIES[self.quantity].describe()
        lo = f"{'(' if self.lo_open else '['}{self.lo:g}"
        hi = f"{self.hi:g}{')' if self.hi_open or np.isinf(self.hi) else ']'}"
        return f"must lie in {lo}, {hi}{' ' + unit if unit not in ('-', '') else ''}"


def _col(name, unit, meaning, rule: Rule, required=False) -> tuple[Column, Rule]:
    return Column(name, unit, meaning, required=required, rule=rule.describe(unit)), rule


_FREQ = Rule("frequency")
_Q = Rule(lo=0.5, lo_open=True)  # below Q = 1/2 a resonance is overdamped: no peak to measure
_MODES = (1, 2, 3)

_AFM = (
    *(
        _col(f"f{n}_free_Hz", "Hz", f"free-lever resonance of mode {n}", _FREQ, required=n == 1)
        for n in _MODES
    ),
    *(_col(f"Q{n}_free", "-", f"quality factor of free mode {n}", _Q) for n in _MODES),
    _col("k_c_N_per_m", "N/m", "static spring constant at the free end, 3EI/L³", Rule("stiffness")),
    _col(
        "tip_position",
        "-",
        "r = L1/L of the tip (blank: solved from two modes)",
        Rule(lo=0.0, hi=1.0, lo_open=True),
    ),
    *(_col(f"fc{n}_Hz", "Hz", f"contact resonance of mode {n}", _FREQ) for n in _MODES),
    *(_col(f"Q{n}", "-", f"quality factor of contact mode {n}", _Q) for n in _MODES),
    _col("lateral_ratio", "-", "lateral spring k_lat/k*", Rule(lo=0.0, hi=100.0)),
    _col("tip_height_over_L", "-", "tip height h/L", Rule(lo=0.0, hi=1.0)),
    _col(
        "tilt_deg", "deg", "tilt of the lever to the sample, free end down", Rule(lo=0.0, hi=60.0)
    ),
    _col("tip_radius_m", "m", "tip radius R (Hertz)", Rule("sphere_radius")),
    _col("load_N", "N", "normal load P (Hertz)", Rule("force")),
    _col("M_tip_Pa", "Pa", "indentation modulus of the tip", Rule("modulus")),
    _col("hardness_Pa", "Pa", "hardness of the sample (plasticity check)", Rule("modulus")),
    _col("fc1_ref_Hz", "Hz", "contact resonance (mode 1) on reference sample 1", _FREQ),
    _col("M_ref_Pa", "Pa", "indentation modulus of reference sample 1", Rule("modulus")),
    _col("fc1_ref2_Hz", "Hz", "contact resonance (mode 1) on reference sample 2", _FREQ),
    _col("M_ref2_Pa", "Pa", "indentation modulus of reference sample 2", Rule("modulus")),
)
_RUM = (
    _col("f0_Hz", "Hz", "free resonance of the oscillator", _FREQ, required=True),
    _col("fc_Hz", "Hz", "contact resonance", _FREQ, required=True),
    _col("K_eff_N_per_m", "N/m", "effective stiffness (lumped model)", Rule("stiffness")),
    _col("mass_kg", "kg", "mass of the rod (rod model)", Rule(lo=0.0, lo_open=True)),
)

#: The contact-resonance AFM table (``contactres afm invert``).
AFM_TABLE = TableSchema(
    "afm-table",
    "one row per point or pixel: resonances of the free and the coupled lever",
    tuple(c for c, _ in _AFM),
)
#: The resonance ultrasound microscope table (``contactres rum invert``).
RUM_TABLE = TableSchema(
    "rum-table",
    "one row per point or pixel: free and contact resonance of the oscillator",
    tuple(c for c, _ in _RUM),
)
RULES = {c.name: r for c, r in (*_AFM, *_RUM)}


def _numbers(raw: pd.DataFrame, col: str, source: str, decimal: str) -> np.ndarray:
    """The cells of ``col`` as floats; blank cells are NaN (not given), text is an error."""
    s = raw[col].astype(str).str.strip()
    if decimal == ",":
        s = s.str.replace(",", ".", regex=False)
    values = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float)
    bad = (np.isnan(values) & (s != "").to_numpy()) | np.isinf(values)
    if bad.any():
        raise ContactresInputError(f"{at_cell(raw, source, bad, col)} is not a finite number")
    return values


def validate_resonance_table(raw: pd.DataFrame, schema: TableSchema, source: str) -> pd.DataFrame:
    """Check a raw table (string cells, a ``line`` column) against ``schema``.

    Returns the table with the schema's columns as floats (NaN where blank or absent), the other
    columns unchanged, and ``line``. Raises ValueError naming file, line, column, value and rule.
    """
    names = set(schema.names)
    lower = {n.lower(): n for n in names}
    for col in raw.columns:
        if col not in names and col.lower() in lower:
            raise ContactresInputError(
                f"{source}: column {shown_value(col)} is not known; did you mean "
                f"{lower[col.lower()]!r}? (names are case-sensitive: the unit is in the name)"
            )
    missing = [c for c in schema.required if c not in raw.columns]
    if missing:
        raise ContactresInputError(f"{source}: required column(s) missing: {', '.join(missing)}")
    if len(raw) == 0:
        raise ContactresInputError(f"{source}: no data rows after the header")
    decimal = raw.attrs.get("decimal", ".")
    out = raw.copy()
    # The columns as given (the output keeps these, not the schema's absent ones).
    out.attrs["given"] = [c for c in raw.columns if c != "line"]
    for c in schema.columns:
        if c.name not in raw.columns:
            out[c.name] = np.nan
            continue
        v = _numbers(raw, c.name, source, decimal)
        rule = RULES[c.name]
        given = ~np.isnan(v)
        if c.required and not given.all():
            raise ContactresInputError(
                f"{where_rows(raw, source, ~given, c.name)}: is empty (required)"
            )
        bad = given & ~rule.accepts(v)
        if bad.any():
            slip = unit_slip(rule.quantity, v[bad][0]) if rule.quantity else None
            hint = f"; it looks like {slip}" if slip else ""
            raise ContactresInputError(f"{at_cell(raw, source, bad, c.name)}: {c.rule}{hint}")
        out[c.name] = v
    return out


def read_resonance_table(path, schema: TableSchema) -> pd.DataFrame:
    """Read and check a table of resonances (:data:`AFM_TABLE` or :data:`RUM_TABLE`).

    The file (CSV: comma, semicolon or tab separated) is never modified. See
    :func:`validate_resonance_table` for what is returned and checked.
    """
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{p}: no such file")
    if p.is_dir():
        raise ContactresInputError(f"{p}: is a directory, expected a table file")
    raw = pick_reader(p).load(p)
    return validate_resonance_table(raw, schema, str(p))
