"""The crystal phase an EBSD export names: its name, lattice constants, Laue and space group.

An ``.ang`` header describes each phase by ``# MaterialName``, ``# Symmetry`` (EDAX's code of
the proper point group: 43 for 432, the rotations of m-3m; 62 for 622, those of 6/mmm) and
``# LatticeConstants a b c α β γ`` (Å, degrees); a ``.ctf`` phase line by ``a;b;c``, ``α;β;γ``,
the name, the Laue group index (11 = m-3m, 9 = 6/mmm) and the space group number (0 = unknown).
The writers of :mod:`._ebsd` take an :class:`EbsdPhase`, so that a Ni map is written as Ni
with Ni's lattice; :func:`ebsd_phase` builds it for a built-in cubic crystal by name.

The elastic constants of :class:`~contactres.materials.Material` carry no lattice constants
(they do not enter contact mechanics), so the table :data:`CUBIC_LATTICES` holds them for the
cubic crystals of ``crystals.csv``: room-temperature lattice constants as commonly tabulated
(e.g. Kittel, *Introduction to Solid State Physics*, 8th ed., ch. 1; Li and Na at the
temperatures of their elastic constants differ little), rounded to 3-4 digits and not
re-checked against a copy of the source here. They label the phase for the reader (orix builds
its crystal structure from them); no orientation depends on them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ContactresInputError

__all__ = ["CUBIC_LATTICES", "EbsdPhase", "ebsd_phase"]

#: Cubic crystals of ``crystals.csv``: (lattice constant a in Å, space group number).
#: 225 Fm-3m (fcc, rock salt), 229 Im-3m (bcc), 227 Fd-3m (diamond), 216 F-43m (zincblende).
CUBIC_LATTICES: dict[str, tuple[float, int]] = {
    "Cu": (3.615, 225), "Al": (4.0495, 225), "Ni": (3.524, 225), "Au": (4.078, 225),
    "Ag": (4.086, 225), "Fe": (2.8665, 229), "W": (3.165, 229), "Si": (5.431, 227),
    "Ge": (5.658, 227), "Pb": (4.950, 225), "Li": (3.51, 229), "Na": (4.29, 229),
    "NaCl": (5.640, 225), "KCl": (6.293, 225), "RbBr": (6.89, 225), "RbI": (7.34, 225),
    "GaAs": (5.653, 216), "diamond": (3.567, 227),
}  # fmt: skip

# Per lattice: EDAX's .ang Symmetry code, the .ctf Laue group index, the Laue group's symbol.
_CODES = {"cubic": ("43", 11, "m-3m"), "hexagonal": ("62", 9, "6/mmm")}


@dataclass(frozen=True)
class EbsdPhase:
    """One crystal phase as EBSD exports describe it.

    Attributes
    ----------
    name : str
        Phase (material) name, written as the .ang ``MaterialName`` and the .ctf phase name.
    lattice : {"cubic", "hexagonal"}
        The Laue group (m-3m or 6/mmm), as elsewhere in :mod:`contactres.polycrystal`.
    a : float
        Lattice constant a, Å.
    c : float or None
        Lattice constant c of a hexagonal phase, Å (None for cubic: c = a).
    space_group : int
        International space group number, 0 when unknown (the .ctf convention).
    """

    name: str
    lattice: str
    a: float
    c: float | None = None
    space_group: int = 0

    def __post_init__(self) -> None:
        if self.lattice not in _CODES:
            raise ContactresInputError(
                f"EbsdPhase lattice {self.lattice!r}: expected one of {sorted(_CODES)}"
            )
        if not self.name.strip() or any(ch in self.name for ch in "\t\r\n"):
            raise ContactresInputError(
                f"EbsdPhase name {self.name!r} must be non-empty text without tabs or newlines"
            )
        for label, v in (("a", self.a), ("c", self.a if self.c is None else self.c)):
            if not (math.isfinite(float(v)) and float(v) > 0):
                raise ContactresInputError(
                    f"EbsdPhase {label} = {v!r} must be a positive length, Å"
                )
        if self.lattice == "hexagonal" and self.c is None:
            raise ContactresInputError("EbsdPhase of a hexagonal lattice needs c (Å)")
        if not 0 <= int(self.space_group) <= 230:
            raise ContactresInputError(
                f"EbsdPhase space_group = {self.space_group!r}: a number 1-230, or 0 for unknown"
            )

    @property
    def lengths(self) -> tuple[float, float, float]:
        """(a, b, c) in Å."""
        c = self.a if self.c is None else self.c
        return (float(self.a), float(self.a), float(c))

    @property
    def angles(self) -> tuple[float, float, float]:
        """(α, β, γ) in degrees."""
        return (90.0, 90.0, 120.0) if self.lattice == "hexagonal" else (90.0, 90.0, 90.0)

    @property
    def ang_symmetry(self) -> str:
        """EDAX's ``# Symmetry`` code (43 cubic, 62 hexagonal)."""
        return _CODES[self.lattice][0]

    @property
    def laue_index(self) -> int:
        """The .ctf / .h5oina Laue group index (11 = m-3m, 9 = 6/mmm)."""
        return _CODES[self.lattice][1]


#: What a map of unknown phase is written as (:func:`~contactres.polycrystal.write_ang` without
#: ``phase``): the name says it; a = 1 Å is a placeholder, not a claim.
UNKNOWN_CUBIC = EbsdPhase("unknown", "cubic", 1.0)


def ebsd_phase(material, lattice: str = "cubic") -> EbsdPhase:
    """The :class:`EbsdPhase` of a built-in cubic crystal (:data:`CUBIC_LATTICES`).

    Parameters
    ----------
    material : str or Material
        A built-in crystal's name (``"Ni"``) or a :class:`~contactres.materials.Material`
        whose ``name`` is one.
    lattice : str
        Must be "cubic" (the table holds cubic crystals; build an :class:`EbsdPhase` for others).

    Raises
    ------
    ContactresInputError
        A name not in the table, a material without a name, another lattice.

    Examples
    --------
    >>> ebsd_phase("Ni")
    EbsdPhase(name='Ni', lattice='cubic', a=3.524, c=None, space_group=225)
    """
    name = material if isinstance(material, str) else getattr(material, "name", None)
    if lattice != "cubic" or name not in CUBIC_LATTICES:
        raise ContactresInputError(
            f"no lattice constants known for {name!r} ({lattice}); the table holds the cubic "
            f"crystals {', '.join(CUBIC_LATTICES)}: pass EbsdPhase(name, lattice, a, c, "
            "space_group) for another phase"
        )
    a, group = CUBIC_LATTICES[name]
    return EbsdPhase(name, "cubic", a, None, group)
