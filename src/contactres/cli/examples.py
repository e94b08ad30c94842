"""CLI: ``contactres examples``: the example files installed with contactres."""

from __future__ import annotations

import textwrap

import click

from ._app import main
from ._common import emit, format_option

#: Width of the plain listing, characters.
PLAIN_WIDTH = 100


@main.command()
@click.argument("names", nargs=-1, metavar="[NAME]...")
@click.option(
    "--copy",
    "copy_to",
    type=click.Path(file_okay=False, dir_okay=True),
    default=None,
    help="Copy the examples (NAMEs, or all) into this folder, created if missing; files of the "
    "same names already there are kept and the copy refused (see --overwrite).",
)
@click.option(
    "--overwrite", is_flag=True, help="With --copy: replace files of the same names in the folder."
)
@format_option()
def examples(names: tuple[str, ...], copy_to: str | None, overwrite: bool, fmt: str) -> None:
    """The example files installed with contactres: list them, print their paths, copy them.

    Without NAME: every example with its size, what it holds and a command that reads it. With
    NAMEs: the path of each installed file, one per line (for scripts:
    contactres qcm analyze "$(contactres examples example_sweeps.csv)" --out qcm_results).
    With --copy DIR: the files copied into DIR, where the commands listed run as they are
    written. --format csv or json gives the table (name, size_bytes, description, command,
    extra, path).

    \b
    Example: contactres examples --copy contactres_examples
    """
    from ..jobs import examples as job

    if overwrite and copy_to is None:
        raise click.UsageError("--overwrite goes with --copy DIR")
    if copy_to == "":
        raise click.BadParameter("give a folder name (an empty one is not)", param_hint="--copy")
    result = job.run(None, job.Settings(names=names, copy_to=copy_to, overwrite=overwrite))
    table = result.table
    if fmt != "plain":
        emit(table, fmt)
    elif names and copy_to is None:
        click.echo("\n".join(table["path"]))
    else:
        if result.copied:
            click.echo(f"copied {len(table)} example file(s) into {copy_to}; from there, run:")
        else:
            click.echo("example files (copy them with --copy DIR; print a path with NAME):")
        for row in table.itertuples(index=False):
            click.echo(f"\n{row.name} ({_size(row.size_bytes)})")
            for line in textwrap.wrap(row.description, PLAIN_WIDTH - 2):
                click.echo(f"  {line}")
            click.echo(f"  $ {row.command}")
            if row.extra:  # the base install cannot run it: say what to add
                click.echo(f"    (needs an optional extra: pip install 'contactres[{row.extra}]')")


def _size(n: int) -> str:
    """A file size in bytes as people read it (1 kB = 1000 bytes)."""
    if n < 1000:
        return f"{n} bytes"
    if n < 1_000_000:
        return f"{n / 1e3:.0f} kB"
    return f"{n / 1e6:.1f} MB"
