"""Columns of a sweep table named with another unit than the schema's (``sphere_radius_mm`` for
``sphere_radius_m``, ``amplitude_nm``): converted to SI and renamed to the schema's name, and
two columns of one quantity refused (issue 30). The TOML keys named so are the sweep reader's
(:mod:`contactres.measurements._sweeps`), with the same :func:`bare_name` and :func:`si_unit`.
"""

from __future__ import annotations

import pandas as pd

from ..errors import ContactresInputError
from ._messages import column_place
from .schema import SWEEP_TABLE

__all__ = ["bare_name", "columns_in_si", "si_unit"]


def si_unit(unit: str) -> str:
    """A schema column's unit as pint reads it ("-" and "text" are none)."""
    return "" if unit in ("-", "text") else unit


def bare_name(name: str) -> str:
    """A column's name without its SI unit suffix: ``sphere_radius_m`` -> ``sphere_radius``."""
    unit = SWEEP_TABLE.column(name).unit
    suffix = "_" + unit.replace("^", "")
    return name[: -len(suffix)] if si_unit(unit) and name.endswith(suffix) else name


def _placed(raw: pd.DataFrame, name: str) -> str:
    """``'amplitude_nm' (column 16)``: a column of ``raw`` by its name and its place."""
    return f"{name!r} ({column_place(raw, list(raw.columns).index(name) + 1)})"


def columns_in_si(raw: pd.DataFrame, source: str) -> pd.DataFrame:
    """``raw`` with every column named with another unit than the schema's (``sphere_radius_mm``
    for ``sphere_radius_m``, ``normal_force_mN``, ``area_cm2``, ``amplitude_nm``) converted to
    SI and renamed to the schema's name (issue 30: a radius in mm gave E ≈ 2 GPa without a
    word). The cells stay text: the numbers are multiplied by the unit's factor, anything else
    (an empty cell, a word) is left for the validation to name."""
    known = set(raw.columns)
    renames: dict[str, tuple[str, float]] = {}
    for col in raw.columns:
        if col in SWEEP_TABLE.names or col == "line":
            continue
        for target in SWEEP_TABLE.names:
            bare, unit = bare_name(target), si_unit(SWEEP_TABLE.column(target).unit)
            if bare == target or not col.startswith(bare + "_"):
                continue
            from ..typed_units import column_unit_factor

            factor = column_unit_factor(col[len(bare) + 1 :], unit)
            if factor is None:
                continue
            # The column of that quantity already there, in SI or in another unit: the two
            # would be one name once renamed (two units of one quantity, amplitude_nm and
            # amplitude_um, were one silently before).
            other = (
                target
                if target in known
                else next((c for c, (t, _) in renames.items() if t == target), None)
            )
            if other is not None:
                first, second = sorted((other, col), key=list(raw.columns).index)
                raise ContactresInputError(
                    f"{source}: columns {_placed(raw, first)} and {_placed(raw, second)} hold "
                    f"the same quantity, {target} in SI; keep one"
                )
            renames[col] = (target, factor)
    if not renames:
        return raw
    out = raw.copy()
    decimal = raw.attrs.get("decimal", ".")
    for col, (_, factor) in renames.items():
        text = out[col].astype(str).str.strip()
        numbers = pd.to_numeric(text.str.replace(decimal, ".", regex=False), errors="coerce")
        scaled = (numbers * factor).map(lambda x: repr(float(x)))
        out[col] = text.where(numbers.isna(), scaled.str.replace(".", decimal, regex=False))
    out = out.rename(columns={c: t for c, (t, _) in renames.items()})
    out.attrs = dict(raw.attrs)
    out.attrs["written_as"] = {t: c for c, (t, _) in renames.items()}  # for the messages
    return out
