"""CLI: ``contactres crystals``: the built-in table of solids."""

from __future__ import annotations

import textwrap

import click

from ._app import main
from ._common import emit, format_option

#: Width of the plain output, characters: two tables and the wrapped sources fit in it.
PLAIN_WIDTH = 100
#: The columns of the first plain table (the others but the source are in the second).
_ELASTIC = ["name", "symmetry", "density_kg_m3", "c11_GPa", "c12_GPa", "c44_GPa", "c13_GPa",
            "c14_GPa", "c33_GPa"]  # fmt: skip


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
    each row. Empty (null in JSON) where a column does not apply. The plain format fits 100
    columns: the elastic constants, then E, ν, the anisotropy and the moduli, then the sources;
    --format csv or json gives every column in one table.

    \b
    Example: contactres crystals --format csv
    """
    from ..jobs import crystals as job

    table = job.run(None, job.Settings()).table
    if fmt != "plain":
        emit(table, fmt)
        return
    elastic = [c for c in _ELASTIC if c in table.columns]
    moduli = ["name", *[c for c in table.columns if c not in elastic and c != "source"]]
    click.echo("elastic constants (GPa) and density (kg/m^3)")
    click.echo(_plain(table[elastic]))
    click.echo("\nisotropic E (GPa) and nu, anisotropy, indentation moduli M of the faces (GPa)")
    click.echo(_plain(table[moduli]))
    click.echo("\nsources")
    width = max(len(str(n)) for n in table["name"])
    for name, source in zip(table["name"], table["source"], strict=True):
        lines = textwrap.wrap(
            str(source),
            PLAIN_WIDTH,
            initial_indent=f"{name:>{width}}  ",
            subsequent_indent=" " * (width + 2),
            break_on_hyphens=False,
        )
        click.echo("\n".join(lines))


def _plain(table) -> str:
    """An aligned text table, empty where a value does not apply, no trailing blanks."""
    text = table.to_string(index=False, na_rep="", float_format=lambda v: f"{v:.6g}")
    return "\n".join(line.rstrip() for line in text.splitlines())
