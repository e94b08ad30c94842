"""CLI: ``contactres crystals`` and ``contactres demo``."""

from __future__ import annotations

import click

from ..crystals import crystal_table
from ..demo import run_demo
from ._app import main
from ._common import emit, format_option


@main.command()
@format_option()
def crystals(fmt: str) -> None:
    """List the built-in cubic crystals.

    Columns: elastic constants c11, c12, c44 (GPa), density (kg/m^3), Zener ratio
    A = 2 c44/(c11 - c12), ν = c12/(c11 + c12), and the source of each row.
    """
    emit(crystal_table(), fmt)


@main.command()
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="contactres-demo",
    show_default=True,
    help="Folder to write the results into (created if missing).",
)
def demo(out: str) -> None:
    """Run the main job on the bundled example data and write its results into OUT."""
    written = run_demo(out, progress=lambda title: click.echo(f"  - {title}", err=True))
    click.echo(f"wrote {len(written)} files into {out}/")
    for p in written:
        click.echo(f"  {p}")
