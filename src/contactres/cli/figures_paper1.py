"""CLI: ``contactres figures paper1``: Figs. 2-5 of paper 1 (figures and CSV)."""

from __future__ import annotations

import click

from ._app import figures
from ._common import figure_format_option


@figures.command("paper1", short_help="Paper 1: Figs. 2-5, the DCSF of a sphere on a half-space.")
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="paper1-figures",
    show_default=True,
    help="Folder to write the figures into (created if missing).",
)
@figure_format_option()
def paper1(out: str, figure_formats: tuple[str, ...]) -> None:
    """Paper 1: the dynamic contact stiffness factor of a sphere on a cubic (001) face.

    Fig. 2 (displacement across the contact), Fig. 3 (the five displacement models at A = 0.5),
    Fig. 4 (WA for A = 0.25 ... 4) and Fig. 5 (WA at A = 2 for ν = 0.1 ... 0.4), against the
    paper's k_l a = ω a √(ρ/C11), Q⁻¹ = 0.02, with the exact rigid-punch curves; and the
    ranking of the models by their largest relative error against exact (k_l a <= 1 and <= 2).
    CSV columns: kla, curve, re, im (DCSF, relative to the static stiffness); Fig. 2: kla,
    rbar (r/a), re_N, im_N, abs_ratio; ranking: zener, model, max_rel_error_kla_le_1,
    max_rel_error_kla_le_2, rank_kla_le_1.

    It takes about 20 s.

    \b
    Example: contactres figures paper1 --out paper1_figures
    """
    from ..apps.paper1 import paper1_set, write_paper1_figures
    from ..jobs import paper1 as job

    progress = lambda step: click.echo(f"  - {step}", err=True)  # noqa: E731
    # The folder is checked (and locked) before the work: a file of the user's under one of the
    # names is refused first, and nothing is changed (issue 27).
    with paper1_set(out, figure_formats) as rs:
        result = job.run(None, job.Settings(), progress)
        written = write_paper1_figures(rs, result=result, figure_formats=figure_formats)
    for path in written:
        click.echo(str(path))
