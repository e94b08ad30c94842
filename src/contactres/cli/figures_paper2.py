"""CLI: ``contactres figures paper2``: the forward figures of paper 2 (figures and CSV)."""

from __future__ import annotations

import click

from ._app import figures
from ._common import figure_format_option


@figures.command("paper2", short_help="Paper 2: the loops of Fig. 2C-D and the shifts of Fig. 1D.")
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="paper2-figures",
    show_default=True,
    help="Folder to write the figures into (created if missing).",
)
@figure_format_option()
def paper2(out: str, figure_formats: tuple[str, ...]) -> None:
    """Paper 2: the loops of Fig. 2C-D and Δf(u0), ΔΓ(u0) of Fig. 1D for both models.

    Cattaneo-Mindlin and Savkoor contacts of a glass sphere (R = 1.1 mm) on a 5 MHz QCM
    (3rd overtone); forces in N, displacements in m, shifts in Hz in the CSV files.

    \b
    Example: contactres figures paper2 --out paper2_figures
    """
    from ..apps.paper2 import paper2_set, write_paper2_figures
    from ..jobs import paper2 as job

    # The folder is checked (and locked) before the work: a file of the user's under one of the
    # names is refused first, and nothing is changed (issue 27).
    with paper2_set(out, figure_formats) as rs:
        result = job.run(None, job.Settings())
        written = write_paper2_figures(rs, result=result, figure_formats=figure_formats)
    for path in written:
        click.echo(str(path))
