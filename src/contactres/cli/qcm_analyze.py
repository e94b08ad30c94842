"""CLI: ``contactres qcm analyze SWEEPS.csv --out DIR`` (the main job of paper 2's analysis).

The results folder is one :class:`contactres.fileio.ResultSet`, opened before the table is read:
an output folder that cannot be written, a result file that would replace an input, or another
run writing into the same folder is refused before any work, and a run that fails or is killed
leaves the folder as it was. Warnings (the data's and numerical ones) become one line each.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import click

from ._app import qcm
from ._common import (
    MagnitudeType,
    MaterialType,
    ValueDefault,
    emit,
    figure_format_option,
    format_option,
    odd_overtone,
    progress_stream,
    save_as_option,
    wrote_line,
)


@qcm.command("analyze")
@click.argument("sweeps", type=click.Path(exists=True))
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    required=True,
    help="Results folder (created if missing): sweeps.csv, loads.csv, summary.json, figures.",
)
@click.option("--area", type=MagnitudeType("area"), help="Acoustically effective area A_eff (m^2).")
@click.option(
    "--overtone",
    type=MagnitudeType("overtone", integer=True),
    callback=odd_overtone,
    help="Overtone order n, dimensionless (odd).",
)
@click.option(
    "--fundamental",
    type=MagnitudeType("frequency"),
    show_default="5e6",
    cls=ValueDefault,
    help="Fundamental frequency f_F (Hz).",
)
@click.option(
    "--n-contacts",
    type=MagnitudeType("contacts", integer=True),
    help="Number of equal contacts, dimensionless (3 for a tripod).",
)
@click.option(
    "--poisson",
    type=MagnitudeType("poisson"),
    show_default="0.17",
    cls=ValueDefault,
    help="Poisson ratio ν (dimensionless) fixed in the JKR fit.",
)
@click.option(
    "--sphere-radius", type=MagnitudeType("qcm_sphere_radius"), help="Sphere radius R (m)."
)
@click.option(
    "--keep-first-ramp",
    is_flag=True,
    help="Use ramp 1 of every load too (default: set aside as running-in).",
)
@click.option(
    "--keep-drift",
    is_flag=True,
    help="Use the sweeps of loads whose ramps drift (default: left out and listed).",
)
@click.option(
    "--remove-drift",
    is_flag=True,
    help="Where the table has a time_s column, remove a drift linear in time from the loads "
    "found drifting and use them if they pass the drift test again.",
)
@click.option(
    "--law-per-load",
    is_flag=True,
    help="Choose Coulomb (Cattaneo-Mindlin/plateau) or Savkoor per load, not once per "
    "experiment (the default pools the loads of an experiment).",
)
@click.option(
    "--bootstrap",
    type=click.IntRange(min=0),
    default=200,
    show_default=True,
    help=(
        "Bootstrap resamples over experiments for the errors of E and γ, dimensionless (0: none;"
        " the errors are then the fit's own, from its residuals, which can differ several-fold)."
    ),
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    show_default="all cores from 10,000 sweeps on, else 1",
    help=(
        "Processes for the loop fits and the plateau's evidence, dimensionless (results identical"
        " to one process)."
    ),
)
@click.option(
    "--sphere-material",
    type=MaterialType("sphere"),
    help="Material of the spheres, a built-in solid ('contactres crystals'), e.g. "
    "soda-lime-glass (alias glass) or fused-silica. With --plate-material: the loss tangent of "
    "the sound the contact radiates into both bodies at the overtone frequency, at the JKR "
    "contact radius (m) of each load, against the measured ΔΓ0/Δf0 (radiation.csv, "
    "radiation_loss.png). Example: --sphere-material glass --plate-material quartz-AT.",
)
@click.option(
    "--plate-material",
    type=MaterialType("plate"),
    help="Material of the plate: quartz-AT (the AT-cut quartz of the QCM, shear along its X "
    "axis) or a built-in solid in its crystal frame. Only with --sphere-material.",
)
@click.option(
    "--coating",
    multiple=True,
    metavar="MATERIAL:THICKNESS",
    help="A film on the plate, thickness in m or with its unit (at most 1; e.g. pmma:250e-9 or "
    "pmma:250nm); repeat for more layers, top first. MATERIAL: pmma (its 1 Hz storage modulus"
    " for the normal load, its modulus at the overtone frequency for κ) or an isotropic solid"
    " of `contactres crystals` (fused-silica, soda-lime-glass, Si3N4). E and γ are then "
    "fitted with the coated plate's contact mechanics (E: sphere and substrate); summary.json"
    " gets each group's uncoated fit and the film's share of κ per load. With "
    "--sphere-material/--plate-material the radiation loss is that of the coated plate (the "
    "coated fit's contact radii; radiation.csv names the film in plate_material).",
)
@click.option("--no-figures", is_flag=True, help="Skip the figures.")
@figure_format_option()
@save_as_option()
@click.option(
    "--report",
    type=click.Choice(["none", "html"]),
    default="none",
    show_default=True,
    help="html: also report.html in OUT, one self-contained page (Table 1, loads, every sweep "
    "with its fit, flags, conventions), no network needed.",
)
@format_option()
def analyze_command(
    sweeps,
    out,
    area,
    overtone,
    fundamental,
    n_contacts,
    poisson,
    sphere_radius,
    keep_first_ramp,
    keep_drift,
    remove_drift,
    law_per_load,
    bootstrap,
    workers,
    sphere_material,
    plate_material,
    coating,
    no_figures,
    figure_formats,
    save_as,
    report,
    fmt,
):
    """Analyse QCM amplitude sweeps (paper 2): stiffness, loss tangent, friction, E and γ.

    SWEEPS is a CSV table with one row per point (columns sweep, amplitude_m, df_Hz,
    dgamma_Hz, normal_force_N; optional experiment, configuration, medium, ramp and the
    constants), or admittance spectra (a table with frequency_Hz and G_S, or a folder with
    index.csv: see 'contactres qcm spectra', whose defaults are used here). Constants missing
    from it come from these options or from a TOML file beside a sweep table (SWEEPS with
    suffix .toml, or contactres.toml). Prints Table 1 (E, γ per configuration
    and medium) and writes everything into OUT. With --sphere-material and --plate-material
    also the loss of the sound each contact radiates into the two bodies, against the measured
    loss tangent (radiation.csv, radiation_loss.png, and a line per group).

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres qcm analyze example_sweeps.csv --out qcm_results
    """
    from ..analysis import Flag, has
    from ..jobs import qcm_sweeps as job
    from ..report import (
        friction_table,
        radiation_lines,
        report_set,
        table1_text,
        withheld_lines,
        write_report,
    )

    if (sphere_material is None) != (plate_material is None):
        given = "--sphere-material" if plate_material is None else "--plate-material"
        raise click.UsageError(
            f"{given} needs the other body too: give --sphere-material and --plate-material "
            "together (e.g. --sphere-material glass --plate-material quartz-AT) or neither",
            click.get_current_context(),
        )
    settings = job.Settings(
        area_m2=area,
        overtone=overtone,
        fundamental_Hz=fundamental,
        n_contacts=n_contacts,
        poisson=poisson,
        sphere_radius_m=sphere_radius,
        keep_first_ramp=keep_first_ramp,
        keep_drift=keep_drift,
        remove_drift=remove_drift,
        law_per_load=law_per_load,
        bootstrap=bootstrap,
        workers=workers,
        sphere_material=sphere_material,
        plate_material=plate_material,
        coating=tuple(coating) or None,
        figures=not no_figures,
    )
    job.coating_layers(settings)  # a bad coating: one line before any work
    if no_figures and _given(click.get_current_context(), "figure_formats"):
        # A format asked for and no figure written would be silently ignored: say so instead.
        raise click.UsageError(
            "--figure-format and --no-figures contradict each other: give one of them",
            click.get_current_context(),
        )
    formats: tuple[str, ...] = ("csv", "json", *(() if no_figures else figure_formats))
    if report == "html":  # the page registered for the job's Result, as its figures are
        formats += ("html",)
    formats += save_as
    source = Path(sweeps)
    # Every file the run reads: the table and the TOML files its constants may come from.
    inputs = (source, source.with_suffix(".toml"), source.parent / "contactres.toml")
    with report_set(job.Result, out, formats, inputs=inputs) as rs:
        reading = job.read(sweeps, settings)
        for line in reading.left_out:
            click.echo(f"contactres: warning: {line}", err=True)
        _echo(reading.warnings)
        steps = job.stages(reading, settings) + (0 if no_figures else 1)
        with (
            warnings.catch_warnings(record=True) as caught,
            click.progressbar(length=steps, label="analysing", file=progress_stream()) as bar,
        ):
            warnings.simplefilter("always")
            done = job.run(reading, settings, progress=lambda _step: bar.update(1))
            results = done.analysis
            written = write_report(done, rs, formats)
            bar.update(steps)
        # The analysis's warnings, then those of the writing, each distinct line once.
        _echo(dict.fromkeys((*done.warnings, *job.warning_lines(caught))))
    for message in results.messages:  # what the analysis found odd in the input
        click.echo(f"contactres: warning: {' '.join(str(message).split())}", err=True)
    if fmt != "plain":
        emit(results.table1(), fmt)
        return
    table1 = table1_text(results)
    if table1.empty:
        click.echo("Table 1: no configuration to fit (no sweep is used)")
    else:
        click.echo("Table 1 (paper 2): E and γ of every configuration and medium")
        click.echo(_text(table1))
        click.echo("± standard errors; 95 % interval: value ± t95 x error (Student t, few repeats)")
        for line in withheld_lines(results):
            click.echo(f"contactres: warning: {line}", err=True)
        click.echo("\nfriction coefficient per load (exact-loop fit, median over experiments)")
        click.echo(_text(friction_table(results)))
    for line in coating_lines(results):
        click.echo(line)
    if results.radiation is not None and len(results.radiation):
        first = results.radiation.iloc[0]
        click.echo(
            f"\nradiation loss of the contacts (sphere {first['sphere_material']}, plate "
            f"{first['plate_material']}; per load in radiation.csv)"
        )
        for line in radiation_lines(results):
            click.echo(line)
    if fmt == "plain":
        n_used = int(results.sweeps["used"].sum())
        models = results.sweeps.loc[results.sweeps["used"], "model"].value_counts().to_dict()
        flagged = int(has(results.sweeps["flags"], Flag.DRIFT).sum())
        click.echo(
            f"{len(results.sweeps)} sweeps, {n_used} used; models: "
            + (", ".join(f"{k} {v}" for k, v in sorted(models.items())) or "none")
            + f"; drift flagged: {flagged}"
        )
        click.echo(wrote_line(written, out))


def coating_lines(results) -> list[str]:
    """With a coating: what it is, and per group the uncoated E and the film's share of κ."""
    coated = [g for g in results.groups if "coating" in g]
    if not coated:
        return []
    lines = [
        f"\ncoated plate: {coated[0]['coating']['label']} (E: sphere and substrate; the "
        "uncoated fit and the film's share of κ at each load, 1 - κ/κ_bare)"
    ]
    for g in coated:
        c = g["coating"]
        # A load left out of the fit whose radius is outside the table has no share (NaN):
        # min and max of the others (a NaN first would be min's answer).
        shares = [s["film_share"] for s in c["loads"] if math.isfinite(s["film_share"])]
        share = f"film share {min(shares):.1%}-{max(shares):.1%}" if shares else "no film share"
        lines.append(
            f"  {g['configuration']}, {g['medium']}: uncoated E = "
            f"{c['uncoated']['E_Pa'] / 1e9:.4g} GPa, γ = "
            f"{c['uncoated']['gamma_J_m2'] * 1e3:.4g} mJ/m²; {share}"
        )
    return lines


def _text(table) -> str:
    """A terminal table: long labels shortened (the files keep them whole), no index."""
    table = table.copy()
    for col in {"configuration", "medium"} & set(table.columns):
        table[col] = [c if len(c) <= 40 else c[:39] + "…" for c in table[col].astype(str)]
    return table.to_string(index=False)


def _echo(lines) -> None:
    """Each warning line on stderr."""
    for line in lines:
        click.echo(f"contactres: warning: {line}", err=True)


def _given(ctx, name: str) -> bool:
    """Whether the user gave the option ``name`` (on the command line or in the environment),
    rather than its default."""
    from click.core import ParameterSource

    return ctx.get_parameter_source(name) in (
        ParameterSource.COMMANDLINE,
        ParameterSource.ENVIRONMENT,
    )
