"""CLI: ``contactres demo``: the main job on the bundled example data."""

from __future__ import annotations

import click

from ._app import main


@main.command()
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="contactres-demo",
    show_default=True,
    help="Folder to write the results into (created if missing).",
)
def demo(out: str) -> None:
    """Run the main job on the bundled example data and write its results into OUT.

    Takes 10-30 s; a line per step on stderr.

    \b
    Example: contactres demo --out contactres-demo
    """
    from ..apps import check_demo_output, write_demo
    from ..jobs import demo as job
    from ..report import friction_table

    # Refused before the work: a path that cannot be the folder, a file of the user's under one
    # of the demo's names (issue 27: never overwritten); nothing is changed then.
    check_demo_output(out)
    progress = lambda title: click.echo(f"  - {title}", err=True)  # noqa: E731
    result = job.run(None, job.Settings(), progress)
    written = write_demo(result, out)
    for line in result.warnings:
        click.echo(f"contactres demo: {line}", err=True)
    click.echo(f"wrote {len(written)} files into {out}/")
    # Then the numbers a user came for, last on the screen: Table 1 (E and γ per group, with
    # the analysis' counts), μ per load, and the modulus map's statistics when that step ran.
    click.echo("\nTable 1 (paper 2): E and γ of every configuration and medium")
    click.echo(_results_lines(result.sweeps_analysis))
    click.echo("\nfriction coefficient per load (exact-loop fit, median over experiments)")
    click.echo(friction_table(result.sweeps_analysis).to_string(index=False))
    if result.map_dataset is not None:
        click.echo("\n" + _map_line(result.map_dataset["M_Pa"].values))


def _results_lines(results) -> str:
    """The analysis' repr without its last line (the Python hint, not a number)."""
    return "\n".join(repr(results).splitlines()[:-1])


def _map_line(M) -> str:
    """The predicted modulus map's statistics: pixels, M range and median (GPa)."""
    import numpy as np

    finite = M[np.isfinite(M)]
    return (
        f"polycrystal map: {finite.size} pixels, M from {finite.min() / 1e9:.4g} to "
        f"{finite.max() / 1e9:.4g} GPa, median {np.median(finite) / 1e9:.4g} GPa"
    )
