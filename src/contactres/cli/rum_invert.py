"""CLI: ``contactres rum invert TABLE --out OUT.csv`` (contact resonance -> contact stiffness)."""

from __future__ import annotations

import click

from ..errors import ContactresInputError
from ._app import rum
from ._common import MagnitudeType, computed_rounded, emit, format_option, step
from ._crystal_face import crystal_face
from ._film import coating_options, film_summary, parse_film_range


@rum.command("invert")
@click.argument("table", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output CSV: the input columns plus rum_model and k_star_N_per_m (N/m); with "
    "--coating also coating, M_film_Pa, film_contact_radius_m, film_weight, film_verdict.",
)
@coating_options()
@click.option(
    "--tip-radius",
    type=MagnitudeType("sphere_radius"),
    default=None,
    help="Radius of the sphere touching the sample, m (with --coating).",
)
@click.option(
    "--force",
    type=MagnitudeType("force"),
    default=None,
    help="Static force on the contact, N (with --coating).",
)
@click.option(
    "--tip-modulus",
    type=MagnitudeType("modulus"),
    default=None,
    show_default="rigid",
    help="Indentation modulus of the sphere, Pa (with --coating).",
)
@format_option()
def rum_invert(
    table, out, coating, substrate, film_range, min_film_weight, tip_radius, force, tip_modulus,
    fmt,
):  # fmt: skip
    """Contact stiffness k* (N/m) of every row of a RUM table.

    TABLE has one row per point or pixel: f0_Hz (free resonance), fc_Hz (contact resonance)
    and the calibration, K_eff_N_per_m (lumped oscillator, (f/f0)² = 1 + k*/K_eff) or mass_kg
    (a rod free at one end with the contact at the other, mode 1: k* = (EA/L)(kL) tan(kL),
    EA/L = 4 m f0²). Other columns are copied to OUT. Writes OUT atomically; prints a summary
    (or the table with --format csv/json).

    With --coating MATERIAL:THICKNESS, --substrate NAME (its 001 face), --tip-radius and
    --force every k* is also turned into the film's indentation modulus M_film_Pa with the
    exact layered contact of the sphere: the film's material gives its Poisson's ratio, its
    modulus is searched in --film-range; film_verdict says whether the film is resolved
    (film), too thin for the contact (film_weight below --min-film-weight: no modulus), too
    thick (the same as a homogeneous film's Hertz inversion) or outside the range (no modulus).

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres rum invert example_rum.csv --out rum_kstar.csv
    """
    from ..fileio import check_output_file, write_csv
    from ..jobs import rum_invert as job

    check_output_file(out, inputs=[table])
    base = None
    if substrate is not None:
        try:
            base = crystal_face(substrate, None, None, None, None, None, "001", None)
        except ContactresInputError as exc:  # the name came with --substrate
            raise ContactresInputError(str(exc).replace("--crystal", "--substrate", 1)) from None
    settings = job.Settings(
        coating=tuple(coating),
        substrate=base,
        tip_radius=tip_radius,
        force=force,
        tip_modulus=tip_modulus,
        film_range=parse_film_range(film_range),
        min_film_weight=min_film_weight,
    )
    done = job.run(table, settings, progress=lambda text: step("rum invert", text))
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
    if done.coating is not None:
        click.echo(film_summary(result, done.coating))
        for message in done.coating.get("notes", ()):  # Hertz's a/R limit: one line each
            click.echo(f"contactres: warning: {message}", err=True)
