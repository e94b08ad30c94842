"""CLI: ``contactres rum invert TABLE --out OUT.csv`` (contact resonance -> contact stiffness)."""

from __future__ import annotations

import click

from ._app import rum
from ._common import computed_rounded, emit, format_option, step


@rum.command("invert")
@click.argument("table", type=click.Path(dir_okay=False))
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output CSV: the input columns plus rum_model and k_star_N_per_m (N/m).",
)
@format_option()
def rum_invert(table, out, fmt):
    """Contact stiffness k* (N/m) of every row of a RUM table.

    TABLE has one row per point or pixel: f0_Hz (free resonance), fc_Hz (contact resonance)
    and the calibration, K_eff_N_per_m (lumped oscillator, (f/f0)² = 1 + k*/K_eff) or mass_kg
    (a rod free at one end with the contact at the other, mode 1: k* = (EA/L)(kL) tan(kL),
    EA/L = 4 m f0²). Other columns are copied to OUT. Writes OUT atomically; prints a summary
    (or the table with --format csv/json).

    Example: contactres rum invert src/contactres/data/example_rum.csv --out rum_kstar.csv
    """
    from ..fileio import check_output_file, write_csv
    from ..jobs import rum_invert as job

    check_output_file(out, inputs=[table])
    done = job.run(table, job.Settings(), progress=lambda text: step("rum invert", text))
    result = done.table
    write_csv(out, computed_rounded(result, done.input_columns))
    if fmt != "plain":
        emit(result, fmt)
        return
    k = result["k_star_N_per_m"]
    click.echo(
        f"{len(result)} rows ({', '.join(sorted(set(result['rum_model'])))} model): k* from "
        f"{k.min():.4g} to {k.max():.4g} N/m, median {k.median():.4g} N/m; wrote {out}"
    )
