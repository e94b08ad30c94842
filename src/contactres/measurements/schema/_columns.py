"""Columns, their rules and the one validator that runs the rules.

A :class:`Rule` is a check a value must pass, held as a callable (``check``: values -> True
where a value passes), with its words for the data dictionary (``text``) and for the error
(``message``). A :class:`Column` carries its rules; a :class:`TableSchema` is an ordered set of
columns. :func:`check_cells` runs a column's rules over the cells of a table and raises the
house's one-line error naming the file, the line, the column, the value and the rule broken;
:func:`check_value` does the same for one value given outside the table (an option, a key of a
TOML file). The rules are the afmformats idea of metadata fields with their validators: the
words and the check live in one place, and the README's column tables are made from the words.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import ContactresInputError
from .._messages import at_cell, shown_value

if TYPE_CHECKING:
    import pandas as pd

    from .._array_table import ArrayTable

__all__ = [
    "LEVELS",
    "Column",
    "Rule",
    "TableSchema",
    "broken_rule",
    "check_cells",
    "check_value",
    "rule",
]

#: Levels of a column: one value per point, one per sweep, or a constant of the instrument or
#: the sample (also one per sweep, and filled from options or a TOML file when absent).
LEVELS = ("point", "sweep", "constant")


#: How alike two column names, ``_folded``, must be (difflib's ratio, 0 to 1) for an unknown
#: one to be taken for a misspelling of a known one: ``poison`` and ``poisson`` are 0.92 alike,
#: ``fc4_Hz`` and ``fc3_Hz`` 0.8 (and differ in a number: never a misspelling).
_NEAR_MISS = 0.85


#: Words that end a column's name without changing what it names (``Poisson_ratio``,
#: ``sweep_id``, ``ramp_number``), folded.
_QUALIFIERS = ("ratio", "id", "name", "number", "order")


def _folded(name: str) -> str:
    """A column name as compared for a misspelling: lower case, without blanks, underscores,
    hyphens and dots (``Sphere Radius`` and ``sphere_radius`` fold alike)."""
    return re.sub(r"[\s_.\-]", "", str(name).lower())


@dataclass(frozen=True)
class Rule:
    """A check one value of a column must pass.

    Attributes
    ----------
    name : short name of the rule (``positive``, ``odd integer``, ...)
    check : callable(values: ndarray) -> bool ndarray, True where a value passes (element-wise;
        never called with the values a column leaves blank)
    text : the rule in words, as the data dictionary shows it (``> 0``)
    message : what the error says after the value, its leading separator included
        (``" is not positive; ..."`` after ``..., value 0.0``; ``": must be > 0"`` after a cell)
    hint : callable(value) -> str, optional: more words for the first bad value (the unit it
        looks like it was typed in), appended to ``message``
    shown : False for a rule every column of its kind has (a finite number, a non-empty label),
        which the dictionary leaves unsaid (its empty rule cell means "any finite number or any
        label")
    """

    name: str
    check: Callable[[np.ndarray], np.ndarray]
    text: str
    message: str
    hint: Callable[[float], str] | None = None
    shown: bool = True

    def accepts(self, values) -> np.ndarray:
        """True where each of ``values`` passes the rule."""
        values = np.asarray(values)
        with np.errstate(invalid="ignore"):
            return np.broadcast_to(np.asarray(self.check(values), dtype=bool), values.shape)

    def explain(self, value) -> str:
        """The error's words for ``value``, which broke the rule."""
        return self.message + (self.hint(value) if self.hint is not None else "")


def rule(name: str, check, text: str, message: str, **more) -> Rule:
    """A :class:`Rule` (short for the schema's many rules)."""
    return Rule(name, check, text, message, **more)


@dataclass(frozen=True)
class Column:
    """One column of a table.

    Attributes
    ----------
    name : column name (its unit is part of the name where it has one: ``df_Hz``)
    unit : SI unit, ``-`` for a number without unit, ``text`` for a label
    meaning : one line for people
    required : the column must be present (input tables only)
    level : ``point``, ``sweep`` or ``constant`` (see :data:`LEVELS`)
    rules : the checks a value must pass, in the order they run (:class:`Rule`; none for an
        output column)
    default : value used when an optional input column is absent (None: no default)
    """

    name: str
    unit: str
    meaning: str
    required: bool = False
    level: str = "point"
    rules: tuple[Rule, ...] = ()
    default: str | float | None = None

    def __post_init__(self):
        if self.level not in LEVELS:
            raise ContactresInputError(f"column {self.name!r}: level must be one of {LEVELS}")

    @property
    def rule(self) -> str:
        """The rules in words (empty: any finite number or any label)."""
        return ", ".join(r.text for r in self.rules if r.shown)


@dataclass(frozen=True)
class TableSchema:
    """An ordered set of :class:`Column` with a name and a one-line description."""

    name: str
    description: str
    columns: tuple[Column, ...]

    @property
    def names(self) -> tuple[str, ...]:
        """Column names, in order."""
        return tuple(c.name for c in self.columns)

    @property
    def required(self) -> tuple[str, ...]:
        """Names of the required columns."""
        return tuple(c.name for c in self.columns if c.required)

    @property
    def optional(self) -> tuple[str, ...]:
        """Names of the optional columns."""
        return tuple(c.name for c in self.columns if not c.required)

    def column(self, name: str) -> Column:
        """The column called ``name`` (KeyError if the table has none)."""
        for c in self.columns:
            if c.name == name:
                return c
        raise KeyError(f"{self.name} has no column {name!r}")

    def where(self, *, level: str | None = None, unit: str | None = None) -> tuple[str, ...]:
        """Names of the columns at ``level`` and/or with ``unit``."""
        return tuple(
            c.name
            for c in self.columns
            if (level is None or c.level == level) and (unit is None or c.unit == unit)
        )

    def check_cells(
        self, table: pd.DataFrame | ArrayTable, source: str, name: str, values=None, given=None
    ) -> None:
        """:func:`check_cells` with the rules of column ``name``."""
        check_cells(table, source, name, self.column(name).rules, values, given)

    def near_miss(self, name: str, absent: Iterable[str]) -> str | None:
        """The column of ``absent`` (names of this table) that ``name``, a column it does not
        know, looks like a misspelling of; None if none.

        Names are compared ``_folded`` (case, blanks and underscores do not count), each
        known name also without its unit suffix (``sphere_radius`` for ``sphere_radius_m``)
        and ``name`` also without a qualifying last word (``Poisson_ratio``, ``sweep_id``):
        equal, or at least ``_NEAR_MISS`` alike by difflib's ratio and holding the same
        numbers (``fc4_Hz`` is a mode of its own, not a typo of ``fc3_Hz``).
        """
        key = _folded(name)
        digits = re.findall(r"\d+", key)
        # The name without a word that qualifies it (Poisson_ratio, sweep_id) is the same name.
        plain = {key[: -len(w)] for w in _QUALIFIERS if key.endswith(w) and len(key) - len(w) > 3}
        best: tuple[float, str] | None = None
        for known in absent:
            for form in {_folded(known), _folded(self._bare(known))}:
                if not form or re.findall(r"\d+", form) != digits:
                    continue
                same = form == key or form in plain
                ratio = 1.0 if same else difflib.SequenceMatcher(None, key, form).ratio()
                if ratio >= _NEAR_MISS and (best is None or ratio > best[0]):
                    best = (ratio, known)
        return None if best is None else best[1]

    def _bare(self, name: str) -> str:
        """``name`` without the suffix of its unit (``_m``, ``_N_per_m``, ``_m2``), if it has
        one; a name this table does not know is returned as it is."""
        try:
            unit = self.column(name).unit
        except KeyError:
            return name
        suffix = "_" + unit.replace("^", "").replace("/", "_per_")
        return name[: -len(suffix)] if unit not in ("-", "text") and name.endswith(suffix) else name

    def check_names(self, columns: Iterable[str], source: str, extra: Iterable[str] = ()) -> None:
        """Raise the one-line error for a column that is not of this table but looks like a
        misspelling of one the table lacks (``poison`` for ``poisson``): a column not of the
        table is not used, so the value would silently give way to the default (issue 27).

        Columns of other names stay allowed (notes, pixel coordinates). ``extra``: more names
        the reader takes (compared as they are written). The ``line`` column of a reader is not
        a column of the file.
        """
        columns = [str(c) for c in columns if str(c) != "line"]
        known = {*self.names, *extra}
        absent = [n for n in (*self.names, *extra) if n not in columns]
        for col in columns:
            if col in known:
                continue
            near = self.near_miss(col, absent)
            if near is not None:
                raise ContactresInputError(
                    f"{source}: column {shown_value(col)} is not a column of the {self.name}; did "
                    f"you mean {near!r}? (a column of another name is not used: the value "
                    f"would be left out{self._fallback(near)})"
                )

    def _fallback(self, name: str) -> str:
        """What stands in for the absent column ``name``, for the near-miss message."""
        try:
            default = self.column(name).default
        except KeyError:
            return ""
        return "" if default is None else f", and {name} taken as its default {_shown(default)}"

    def markdown(self, with_required: bool = False) -> str:
        """The table as a Markdown table (the README's column tables are checked against this)."""
        head = ["column", "unit", *(["required"] if with_required else []), "meaning"]
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for c in self.columns:
            cells = [f"`{c.name}`", c.unit]
            if with_required:
                cells.append("yes" if c.required else "no")
            text = f" ({c.rule})" if c.rule else ""
            default = "" if c.default is None else f"; default {_shown(c.default)}"
            cells.append(f"{c.meaning}{text}{default}")
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)


def _shown(value) -> str:
    return f"{value:g}" if isinstance(value, float) else f'"{value}"'


# --------------------------------------------------------------------------------------------
# The one validator


def broken_rule(rules, values, given=None) -> tuple[Rule, np.ndarray] | None:
    """The first of ``rules`` that some of ``values`` break, with the mask of those values.

    ``given`` (bool mask) limits the check to the values given (a blank cell is "not given":
    whether it may be blank is the reader's question, not a rule's). None if every rule holds.
    """
    values = np.asarray(values)
    given = np.ones(values.shape, dtype=bool) if given is None else np.asarray(given, dtype=bool)
    for r in rules:
        bad = given & ~r.accepts(values)
        if bad.any():
            return r, bad
    return None


def check_cells(
    table: pd.DataFrame | ArrayTable, source: str, name: str, rules, values=None, given=None
):
    """Raise the one-line error for the first cell of column ``name`` that breaks a rule.

    Parameters
    ----------
    table : DataFrame or ArrayTable
        The rows as read, with their ``line`` numbers; the value shown is ``table[name]`` as
        written there.
    source : str
        The file (or ``<table>``).
    name : str
        The column.
    rules : sequence of Rule
        Run in order; the first rule broken anywhere is the one reported.
    values : array, optional
        The cells as numbers, aligned with the rows of ``table`` (default ``table[name]``).
    given : bool array, optional
        Which cells are given (default: all).

    Raises
    ------
    ContactresInputError
        ``<file>, line <n>, column '<name>'[ (<k> such rows: lines ...)]: value <v><message>``.
    """
    values = np.asarray(table[name]) if values is None else np.asarray(values)
    found = broken_rule(rules, values, given)
    if found is not None:
        r, bad = found
        first = values[np.flatnonzero(bad)[0]]
        raise ContactresInputError(f"{at_cell(table, source, bad, name)}{r.explain(first)}")


def check_value(name: str, value, where: str, shown: str, rules) -> None:
    """Raise ``<where>: <name> = <shown><message>`` if ``value`` breaks one of ``rules``."""
    found = broken_rule(rules, np.array([value]))
    if found is not None:
        raise ContactresInputError(f"{where}: {name} = {shown}{found[0].explain(value)}")
