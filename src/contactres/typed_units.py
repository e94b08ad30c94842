"""Values typed with their unit, converted to SI at the input boundary.

contactres computes in SI and its plain numbers are SI. Where a user types a value with its unit
(an option ``--sphere-radius 1.1mm``, a TOML value ``sphere_radius = "1.1 mm"``) or names a
column with its unit (``sphere_radius_mm``), the value is converted here, once, with pint (the
well-kept unit library of scientific Python: https://pint.readthedocs.io), and checked for its
dimension: a force typed for a length is refused in one line, never converted. Nothing
downstream sees a unit.

pint is imported only when a unit is typed: a plain number never pays its import (~0.4 s). The
units are read with pint's application registry, the one pint's documentation asks libraries to
use: pint builds it on its first use in the process (~0.2 s of CPU) and keeps it, so that a
command with several values typed with units, or a table with several unit columns, pays that
once, not once per value as a fresh registry per call did (issue 31). contactres keeps no
registry of its own and hands out no pint object: every value leaves here as a float in SI.
"""

from __future__ import annotations

import re
import threading

from .errors import ContactresInputError

__all__ = ["column_unit_factor", "has_unit", "to_si"]

#: Held while pint's application registry is fetched: pint builds it on the first attribute read
#: without a lock (pint issue #2039), and a thread reading it half-built found no "mm" (to_si:
#: "unknown unit"; column_unit_factor: None, the column silently not taken as millimetres).
_FIRST_USE = threading.Lock()

# A number, then optional spaces, then something that starts like a unit (a letter, µ, %).
_WITH_UNIT = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*[A-Za-zµμΩ°%]")
# A unit written with a trailing power, as in a column name: cm2 -> cm^2, m3 -> m^3.
_TRAILING_POWER = re.compile(r"(?<=[A-Za-zµ])(\d)$")


def has_unit(text) -> bool:
    """True if ``text`` is a string holding a number followed by a unit (``"1.1 mm"``); a
    plain number (``"1e-3"``, ``"nan"``) is not."""
    if not isinstance(text, str) or not _WITH_UNIT.match(text):
        return False
    try:
        float(text)
    except ValueError:
        return True
    return False


def _registry():
    """pint's application registry (pint, and the registry, loaded on the first value typed with
    a unit; module docstring)."""
    import pint

    with _FIRST_USE:
        registry = pint.get_application_registry()
        registry.Quantity  # noqa: B018 - builds the registry here, under the lock, if not yet built
    return registry


def _units_in_words(unit: str) -> str:
    return unit if unit else "a plain number (dimensionless)"


def to_si(text: str, unit: str, what: str) -> float:
    """The value of ``text`` (a number with its unit, e.g. ``"1.1 mm"``) in the SI unit ``unit``.

    Parameters
    ----------
    text : str
        As typed: a number, optional spaces, a unit pint knows (``mm``, ``µm``, ``um``, ``nm``,
        ``mN``, ``MHz``, ``GPa``, ``g/cm^3``, ``cm^2``, ...).
    unit : str
        The SI unit of the quantity (``"m"``, ``"N"``, ``"Pa"``, ``"m^2"``, ``"kg m^-2 s^-1"``;
        ``""`` for a dimensionless one, which refuses every unit).
    what : str
        Who gave the value, for the message (``"--sphere-radius"``, ``"data.toml: sphere_radius"``).

    Returns
    -------
    float
        The magnitude in ``unit``.

    Raises
    ------
    ContactresInputError
        One line naming ``what`` and the text: a decimal comma, a unit pint does not know, a
        unit of another dimension than ``unit``.
    """
    shown = text.strip()
    if "," in shown:
        raise ContactresInputError(
            f"{what} {shown!r}: write the number with a decimal point (a comma is ambiguous)"
        )
    import pint

    ureg = _registry()
    try:
        quantity = ureg.Quantity(shown)
    except pint.UndefinedUnitError as exc:
        raise ContactresInputError(
            f"{what} {shown!r}: unknown unit {' '.join(str(exc).split())}; give the value in "
            f"{_units_in_words(unit)} or with a unit such as mm, µm, mN, MHz, GPa"
        ) from None
    except Exception:  # pint's parser raises several kinds on text it cannot read
        raise ContactresInputError(
            f"{what} {shown!r} is not a number with a unit (e.g. 1.1 mm)"
        ) from None
    target = ureg.Quantity(1.0, unit) if unit else ureg.Quantity(1.0)
    if quantity.dimensionality != target.dimensionality:
        if not f"{quantity.units:~P}":
            # No unit at all: an expression pint evaluated ("2:3", "1/2"), not a plain number
            # (has_unit sent it here); "is in , a quantity of another kind" would say nothing.
            raise ContactresInputError(
                f"{what} {shown!r} is not a number with a unit (e.g. 1.1 mm); give the value "
                f"in {_units_in_words(unit)} or with its unit"
            )
        raise ContactresInputError(
            f"{what} {shown!r} is in {quantity.units:~P}, a quantity of another kind than "
            f"{_units_in_words(unit)}"
        )
    return float(quantity.to(target.units).magnitude)


def column_unit_factor(suffix: str, unit: str) -> float | None:
    """The factor from a column's unit suffix to the SI unit ``unit``, or None.

    ``column_unit_factor("mm", "m")`` is 1e-3 (a column ``sphere_radius_mm`` holds millimetres);
    ``column_unit_factor("cm2", "m^2")`` 1e-4 (a trailing digit is a power). None when the
    suffix is no unit, or one of another dimension: the column is then not this quantity.
    """
    if not unit or not suffix:
        return None

    ureg = _registry()
    name = _TRAILING_POWER.sub(r"^\1", suffix.replace("_per_", "/"))
    try:
        given = ureg.Quantity(1.0, name)
        target = ureg.Quantity(1.0, unit)
    except Exception:  # not a unit pint can read: not a unit suffix
        return None
    if given.dimensionality != target.dimensionality:
        return None
    return float(given.to(target.units).magnitude)
