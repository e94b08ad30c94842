"""Built-in table of cubic crystals (``data/crystals.csv``, with the source of each row).

A ground-layer table: it returns the raw constants as :class:`CrystalRecord` and knows nothing of
:class:`contactres.Material`; ``Material.crystal(name)`` builds the solid from the record. The CSV
is read on every call (a few hundred bytes, ~0.1 ms with the standard library's csv module), so
there is no cache.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from importlib import resources
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["CrystalRecord", "crystal_names", "crystal_record", "crystal_table"]

_GPa = 1e9


@dataclass(frozen=True)
class CrystalRecord:
    """One row of the built-in table, in SI units.

    Attributes
    ----------
    name : the crystal's name as written in the table (e.g. ``"Cu"``)
    c11, c12, c44 : cubic elastic constants in the cube-axis frame, Pa
    density : mass density, kg/m^3
    source : where the constants come from
    """

    name: str
    c11: float
    c12: float
    c44: float
    density: float
    source: str


def _rows() -> list[dict[str, str]]:
    """The table's rows as strings (the standard library's csv: no pandas on this path)."""
    with resources.files("contactres").joinpath("data/crystals.csv").open("r") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    return list(csv.DictReader(lines))


def crystal_names() -> list[str]:
    """Names of the built-in crystals, in table order."""
    return [row["name"] for row in _rows()]


def crystal_record(name: str) -> CrystalRecord:
    """The built-in crystal ``name`` (case-insensitive) as a :class:`CrystalRecord` (SI units).

    Raises
    ------
    ValueError
        For an unknown name; the message lists the known ones.
    """
    rows = _rows()
    key = str(name).strip().lower()
    match = [row for row in rows if row["name"].lower() == key]
    if not match:
        known = ", ".join(row["name"] for row in rows)
        raise ValueError(f"unknown crystal {name!r}; known crystals: {known}")
    row = match[0]
    return CrystalRecord(
        name=row["name"],
        c11=float(row["c11_GPa"]) * _GPa,
        c12=float(row["c12_GPa"]) * _GPa,
        c44=float(row["c44_GPa"]) * _GPa,
        density=float(row["density_kg_m3"]),
        source=row["source"],
    )


def crystal_table() -> pd.DataFrame:
    """The built-in crystals with their Zener ratio A and ν = C12/(C11 + C12) added.

    Columns: name, c11_GPa, c12_GPa, c44_GPa, density_kg_m3, zener, poisson, source.
    """
    import pandas as pd  # only the table needs pandas; records and names do not

    with resources.files("contactres").joinpath("data/crystals.csv").open("r") as fh:
        t = pd.read_csv(fh, comment="#")
    t["zener"] = 2 * t.c44_GPa / (t.c11_GPa - t.c12_GPa)
    t["poisson"] = t.c12_GPa / (t.c11_GPa + t.c12_GPa)
    cols = ["name", "c11_GPa", "c12_GPa", "c44_GPa", "density_kg_m3", "zener", "poisson", "source"]
    return t[cols]
