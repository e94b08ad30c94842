"""CLI: ``contactres crystals``: the built-in crystal table."""

from __future__ import annotations

from ._app import main
from ._common import emit, format_option


@main.command()
@format_option()
def crystals(fmt: str) -> None:
    """List the built-in cubic crystals.

    Columns: elastic constants c11, c12, c44 (GPa), density (kg/m^3), Zener ratio
    A = 2 c44/(c11 - c12), ν = c12/(c11 + c12), the indentation modulus M (GPa) of the
    (001), (011) and (111) faces (paper 1, Eq. 4: a rigid sphere sees an isotropic E* = M),
    and the source of each row.
    """
    from ..crystals import crystal_table
    from ..materials import Material
    from ..normal.anisotropic import indentation_modulus

    table = crystal_table()
    solids = [Material.crystal(name) for name in table["name"]]
    for label, normal in (
        ("M001_GPa", (0, 0, 1)),
        ("M011_GPa", (0, 1, 1)),
        ("M111_GPa", (1, 1, 1)),
    ):
        table.insert(
            table.columns.get_loc("source"),
            label,
            [indentation_modulus(m.rotated(normal)) / 1e9 for m in solids],
        )
    emit(table, fmt)
