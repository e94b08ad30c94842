"""Built-in table of cubic crystals (``data/crystals.csv``, with the source of each row)."""

from __future__ import annotations

from functools import lru_cache
from importlib import resources

import pandas as pd

from .materials import Material

__all__ = ["crystal_names", "crystal_table", "get_crystal"]

_GPa = 1e9


@lru_cache(maxsize=1)
def _raw_table() -> pd.DataFrame:
    with resources.files("contactres").joinpath("data/crystals.csv").open("r") as fh:
        return pd.read_csv(fh, comment="#")


def crystal_names() -> list[str]:
    """Names of the built-in crystals, in table order."""
    return list(_raw_table()["name"])


def get_crystal(name: str) -> Material:
    """The built-in crystal ``name`` (case-insensitive) as a :class:`Material` in its cube frame.

    Raises
    ------
    ValueError
        For an unknown name; the message lists the known ones.
    """
    table = _raw_table()
    match = table[table["name"].str.lower() == str(name).strip().lower()]
    if match.empty:
        raise ValueError(f"unknown crystal {name!r}; known crystals: {', '.join(crystal_names())}")
    row = match.iloc[0]
    return Material.cubic(
        row.c11_GPa * _GPa,
        row.c12_GPa * _GPa,
        row.c44_GPa * _GPa,
        density=row.density_kg_m3,
        name=row["name"],
    )


def crystal_table() -> pd.DataFrame:
    """The built-in crystals with their Zener ratio A and ν = C12/(C11 + C12) added.

    Columns: name, c11_GPa, c12_GPa, c44_GPa, density_kg_m3, zener, poisson, source.
    """
    t = _raw_table().copy()
    t["zener"] = 2 * t.c44_GPa / (t.c11_GPa - t.c12_GPa)
    t["poisson"] = t.c12_GPa / (t.c11_GPa + t.c12_GPa)
    cols = ["name", "c11_GPa", "c12_GPa", "c44_GPa", "density_kg_m3", "zener", "poisson", "source"]
    return t[cols]
