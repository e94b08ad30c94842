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
    from ..apps import write_demo
    from ..fileio import ensure_dir
    from ..jobs import demo as job

    ensure_dir(out)  # a path that cannot be the folder is refused before the work
    progress = lambda title: click.echo(f"  - {title}", err=True)  # noqa: E731
    result = job.run(None, job.Settings(), progress)
    written = write_demo(result, out)
    for line in result.warnings:
        click.echo(f"contactres demo: {line}", err=True)
    # The numbers a user came for: the QCM analysis' counts and Table 1 (E and γ per group).
    click.echo("\n".join(repr(result.sweeps_analysis).splitlines()[:-1]))  # not the Python hint
    click.echo(f"wrote {len(written)} files into {out}/")
    for p in written:
        click.echo(f"  {p}")
