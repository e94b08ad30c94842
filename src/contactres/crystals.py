"""Built-in tables of solids, with the source of each row.

Two CSV files of ``contactres/data``: ``crystals.csv`` holds the cubic crystals (c11, c12, c44),
``materials.csv`` the other solids, one ``symmetry`` per row: ``trigonal`` (alpha-quartz,
sapphire: c11, c12, c13, c14, c33, c44) or ``isotropic`` (glasses, amorphous Si3N4: E, ν). The
two files keep their own columns, so the cubic table did not change when the others were added.

A ground-layer table: it returns the raw constants as :class:`CrystalRecord` and knows nothing of
:class:`contactres.Material`; ``Material.crystal(name)`` builds the solid from the record. The
CSVs are read on every call (a few hundred bytes each, ~0.1 ms with the standard library's csv
module), so there is no cache.
"""

from __future__ import annotations

import csv
from dataclasses import asdict, dataclass
from importlib import resources
from typing import TYPE_CHECKING

from ._summary import Summarised, clipped, number
from .errors import ContactresInputError

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["CrystalRecord", "crystal_names", "crystal_record", "crystal_table"]

_GPa = 1e9

# The CSV columns each symmetry of materials.csv fills; every other constant cell must be empty.
_SYMMETRIES: dict[str, tuple[str, ...]] = {
    "trigonal": ("c11_GPa", "c12_GPa", "c13_GPa", "c14_GPa", "c33_GPa", "c44_GPa"),
    "isotropic": ("E_GPa", "nu"),
}
_CONSTANT_COLUMNS = (
    "c11_GPa",
    "c12_GPa",
    "c13_GPa",
    "c14_GPa",
    "c33_GPa",
    "c44_GPa",
    "E_GPa",
    "nu",
)


# repr=False: the summary (Summarised, _facts) gives the constants in GPa and clips the source.
@dataclass(frozen=True, repr=False)
class CrystalRecord(Summarised):
    """One row of the built-in tables, in SI units.

    Attributes
    ----------
    name : the solid's name as written in the table (e.g. ``"Cu"``, ``"quartz"``)
    c11, c12, c44 : elastic constants in the crystal frame, Pa. For an isotropic row they follow
        from E and ν: c11 = λ + 2μ, c12 = λ, c44 = μ (Lamé constants)
    density : mass density, kg/m^3
    source : where the constants come from
    symmetry : ``"cubic"``, ``"trigonal"`` or ``"isotropic"``
    c13, c14, c33 : the further trigonal constants, Pa (None for the other symmetries)
    E, nu : Young's modulus (Pa) and Poisson's ratio of an isotropic row (None otherwise)
    """

    name: str
    c11: float
    c12: float
    c44: float
    density: float
    source: str
    symmetry: str = "cubic"
    c13: float | None = None
    c14: float | None = None
    c33: float | None = None
    E: float | None = None
    nu: float | None = None

    def _facts(self) -> list[tuple[str, str]]:
        """Name, symmetry, the constants in GPa (E and ν of an isotropic row), ρ, the source."""
        facts = [("", repr(self.name)), ("", self.symmetry)]
        if self.E is not None and self.nu is not None:
            facts += [("E", number(self.E, "GPa", 1e9)), ("ν", number(self.nu))]
        else:
            names = ["c11", "c12", "c13", "c14", "c33", "c44"]
            shown = [(n, getattr(self, n)) for n in names if getattr(self, n) is not None]
            facts += [(n.upper(), number(v, "GPa", 1e9)) for n, v in shown]
        facts.append(("ρ", number(self.density, "kg/m³")))
        return [*facts, ("source", clipped(self.source, 60))]


def _rows(filename: str) -> list[dict[str, str]]:
    """The rows of ``data/<filename>`` as strings (the standard library's csv: no pandas)."""
    with resources.files("contactres").joinpath(f"data/{filename}").open("r") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    return list(csv.DictReader(lines))


def _cubic_record(row: dict[str, str]) -> CrystalRecord:
    return CrystalRecord(
        name=row["name"],
        c11=float(row["c11_GPa"]) * _GPa,
        c12=float(row["c12_GPa"]) * _GPa,
        c44=float(row["c44_GPa"]) * _GPa,
        density=float(row["density_kg_m3"]),
        source=row["source"],
    )


def _other_record(row: dict[str, str]) -> CrystalRecord:
    """A row of materials.csv; a malformed row (wrong or missing cells) is a ValueError."""
    name, symmetry = row["name"], row["symmetry"]
    if symmetry not in _SYMMETRIES:
        raise ContactresInputError(f"materials.csv row {name!r}: unknown symmetry {symmetry!r}")
    needed = _SYMMETRIES[symmetry]
    filled = {c for c in _CONSTANT_COLUMNS if row[c].strip()}
    if filled != set(needed):
        raise ContactresInputError(
            f"materials.csv row {name!r} ({symmetry}) must fill exactly {', '.join(needed)}; "
            f"it fills {', '.join(sorted(filled)) or 'none'}"
        )
    density, source = float(row["density_kg_m3"]), row["source"]
    if symmetry == "isotropic":
        E, nu = float(row["E_GPa"]) * _GPa, float(row["nu"])
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        mu = E / (2 * (1 + nu))
        return CrystalRecord(
            name=name,
            c11=lam + 2 * mu,
            c12=lam,
            c44=mu,
            density=density,
            source=source,
            symmetry=symmetry,
            E=E,
            nu=nu,
        )
    c11, c12, c13, c14, c33, c44 = (
        float(row[f"{k}_GPa"]) * _GPa for k in ("c11", "c12", "c13", "c14", "c33", "c44")
    )
    return CrystalRecord(
        name=name,
        c11=c11,
        c12=c12,
        c44=c44,
        density=density,
        source=source,
        symmetry=symmetry,
        c13=c13,
        c14=c14,
        c33=c33,
    )


def _records() -> list[CrystalRecord]:
    """Every built-in solid: the cubic table first, then the others, each in file order."""
    cubic = [_cubic_record(row) for row in _rows("crystals.csv")]
    return cubic + [_other_record(row) for row in _rows("materials.csv")]


def crystal_names() -> list[str]:
    """Names of the built-in solids: the cubic crystals, then the others, in table order.

    Examples
    --------
    >>> from contactres import crystal_names
    >>> names = crystal_names()
    >>> "Cu" in names and "Si" in names
    True
    """
    return [row["name"] for row in _rows("crystals.csv") + _rows("materials.csv")]


def crystal_record(name: str) -> CrystalRecord:
    """The built-in solid ``name`` (case-insensitive) as a :class:`CrystalRecord` (SI units).

    Raises
    ------
    ValueError
        For an unknown name; the message lists the known ones.
    """
    key = str(name).strip().lower()
    for filename, build in (("crystals.csv", _cubic_record), ("materials.csv", _other_record)):
        for row in _rows(filename):
            if row["name"].lower() == key:
                return build(row)
    raise ContactresInputError(
        f"unknown crystal {name!r}; known crystals: {', '.join(crystal_names())}"
    )


def crystal_table() -> pd.DataFrame:
    """The built-in solids, one row each, in GPa and kg/m^3.

    Columns: name, c11_GPa, c12_GPa, c44_GPa, c13_GPa, c14_GPa, c33_GPa, density_kg_m3, symmetry,
    E_GPa, nu, zener, poisson, source. The Zener ratio A = 2 C44/(C11 - C12) and
    ν = C12/(C11 + C12) (paper 1's cubic parameters) are given where they apply: for the cubic
    rows and the isotropic ones (A = 1 and ν = Poisson's ratio); NaN for the trigonal rows, as
    are the constants a row's symmetry does not have.

    Examples
    --------
    >>> from contactres import crystal_table
    >>> t = crystal_table()
    >>> row = t.set_index("name").loc["Si"]
    >>> print(row["c11_GPa"], row["c12_GPa"], row["c44_GPa"], row["symmetry"])
    165.7 63.9 79.6 cubic
    """
    import pandas as pd  # only the table needs pandas; records and names do not

    t = pd.DataFrame([asdict(r) for r in _records()])
    for col in ("c11", "c12", "c44", "c13", "c14", "c33", "E"):
        t[f"{col}_GPa"] = t[col].astype(float) / _GPa
    t["nu"] = t["nu"].astype(float)
    t["density_kg_m3"] = t["density"]
    cubic_like = t["symmetry"].isin(["cubic", "isotropic"])
    t["zener"] = (2 * t.c44_GPa / (t.c11_GPa - t.c12_GPa)).where(cubic_like)
    t["poisson"] = (t.c12_GPa / (t.c11_GPa + t.c12_GPa)).where(cubic_like)
    cols = [
        "name",
        "c11_GPa",
        "c12_GPa",
        "c44_GPa",
        "c13_GPa",
        "c14_GPa",
        "c33_GPa",
        "density_kg_m3",
        "symmetry",
        "E_GPa",
        "nu",
        "zener",
        "poisson",
        "source",
    ]
    return t[cols]
