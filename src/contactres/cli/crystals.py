"""CLI: ``contactres crystals``: the built-in table of solids."""

from __future__ import annotations

from ._app import main
from ._common import emit, format_option

# Faces given by cube-axis Miller indices: meaningful for cubic (and isotropic) solids only.
_CUBIC_FACES = (("M011_GPa", (0, 1, 1)), ("M111_GPa", (1, 1, 1)))


@main.command()
@format_option()
def crystals(fmt: str) -> None:
    """List the built-in solids: cubic crystals, trigonal ones (quartz, sapphire), isotropic ones.

    Columns: elastic constants c11, c12, c44 (GPa; of an isotropic solid from E and ν), the
    trigonal c13, c14, c33 (GPa), density (kg/m^3), symmetry, E (GPa) and ν of an isotropic
    solid, Zener ratio A = 2 c44/(c11 - c12) and ν = c12/(c11 + c12) (cubic and isotropic rows
    only), the indentation modulus M (GPa; paper 1, Eq. 4: a rigid sphere sees an isotropic
    E* = M) of the face normal to the crystal z axis (M001: the (001) face of a cubic crystal, the
    basal Z-cut face of a trigonal one) and of the cubic (011) and (111) faces, and the source of
    each row. Empty (null in JSON) where a column does not apply.
    """
    import numpy as np

    from ..crystals import crystal_table
    from ..materials import Material
    from ..normal.anisotropic import indentation_modulus

    table = crystal_table()
    solids = [Material.crystal(name) for name in table["name"]]
    cubic_like = table["symmetry"].isin(["cubic", "isotropic"]).to_numpy()
    at = table.columns.get_loc("source")
    table.insert(at, "M001_GPa", [indentation_modulus(m.rotated((0, 0, 1))) / 1e9 for m in solids])
    for label, normal in _CUBIC_FACES:
        values = [
            indentation_modulus(m.rotated(normal)) / 1e9 if ok else np.nan
            for m, ok in zip(solids, cubic_like, strict=True)
        ]
        table.insert(table.columns.get_loc("source"), label, values)
    emit(table, fmt)
