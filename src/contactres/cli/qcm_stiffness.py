"""CLI: ``contactres qcm stiffness EXPORT --area A --n-contacts N --out DIR``.

The contact stiffness against time from a QCM-D instrument export: Δf + iΔΓ of every overtone
becomes κ + iωξ of one contact with paper 2's Eq. 2, κ + iωξ = (Δf + iΔΓ)/P with
P = n_P/(2nπ² A_eff Z_q) (:func:`contactres.stiffness_from_shifts`). The export is read by the
plug-ins of :mod:`contactres.measurements.readers.exports`; what the file does not say is asked
for by an option (one line naming the file and the missing choice, exit code 2).

The results folder is one :class:`contactres.fileio.ResultSet` (whole or not at all):
``stiffness.csv`` (time_s, overtone, df_Hz, dgamma_Hz, kappa_N_per_m, omega_xi_N_per_m),
``stiffness.json`` (the conventions the file was read with, the constants and the equation) and
``stiffness.png`` (κ and ωξ against time, one colour per overtone).
"""

from __future__ import annotations

from pathlib import Path

import click

from ._app import qcm
from ._common import MagnitudeType, figure_format_option, save_as_option, step, wrote_line
from ._export_options import conventions, export_options, reader_names


def __getattr__(name: str):
    """``COLUMN_UNITS`` (the units of stiffness.csv's columns) is the job's and
    ``READER_NAMES`` (:func:`reader_names`) the registry's, loaded on use."""
    if name == "COLUMN_UNITS":
        from ..jobs.qcm_stiffness import COLUMN_UNITS

        return COLUMN_UNITS
    if name == "READER_NAMES":
        return reader_names()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@qcm.command("stiffness", short_help="Contact stiffness κ + iωξ against time from a QCM-D export.")
@click.argument("export", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    required=True,
    help="Results folder (created if missing): stiffness.csv, stiffness.json, stiffness.png.",
)
@click.option(
    "--area",
    type=MagnitudeType("area"),
    required=True,
    help="Acoustically effective area A_eff of the electrode, m^2.",
)
@click.option(
    "--n-contacts",
    type=MagnitudeType("contacts", integer=True),
    required=True,
    help="Number of equal contacts n_P on that area, dimensionless.",
)
@export_options()
@click.option(
    "--fundamental",
    type=MagnitudeType("frequency"),
    help="Fundamental frequency f_F of the quartz, Hz: needed for ΔΓ = ΔD n f_F/2 when the "
    "file holds shifts only.",
    show_default="f_n/n from a file of absolute frequencies",
)
@click.option(
    "--zq",
    type=MagnitudeType("impedance"),
    default="8.8e6",
    show_default=True,
    help="Acoustic impedance Z_q of AT-cut quartz, kg m^-2 s^-1.",
)
@figure_format_option()
@save_as_option()
def stiffness_command(
    export,
    out,
    area,
    n_contacts,
    reader,
    df_per_overtone,
    dissipation_scale,
    baseline,
    time_unit,
    channel,
    overtone,
    fundamental,
    zq,
    figure_formats,
    save_as,
):
    """Contact stiffness κ + iωξ against time from a QCM-D export (paper 2, Eq. 2).

    EXPORT is the text export of a QCM-D instrument (QSense, AWSensors, QCM-I, openQCM). For
    every point and overtone n: κ = Δf/P and ωξ = ΔΓ/P, N/m per contact, with
    P = n_P/(2nπ² A_eff Z_q), Δf the frequency shift (Hz, not divided by n) and ΔΓ the shift of
    the half-bandwidth (Hz; Γ = D f_n/2). Writes stiffness.csv, stiffness.json (the conventions
    the file was read with) and stiffness.png into OUT.

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres qcm stiffness example_qcmd.csv --dissipation-scale \\
        1e-6 --fundamental 4.95e6 --area 2e-5 --n-contacts 3 --out qcmd_stiffness

    A QSense export with Δf/n, D in ppm, time in s, three contacts on 0.2 cm²:

    \b
        contactres qcm stiffness run.txt --df-divided-by-n --dissipation-scale 1e-6 \\
            --time-unit s --fundamental 4.95e6 --area 2e-5 --n-contacts 3 --out run-stiffness
    """
    from ..jobs import qcm_stiffness as job
    from ..report import report_set, write_report

    source = Path(export)
    read_with = conventions(
        df_per_overtone, dissipation_scale, baseline, time_unit, channel, overtone
    )
    settings = job.Settings(area, n_contacts, reader, {**read_with, "fundamental": fundamental}, zq)
    progress = lambda text: step("qcm stiffness", text)  # noqa: E731
    # The folder is checked (and locked) before the export is read: an output error comes first.
    formats = ("csv", "json", *figure_formats, *save_as)
    with report_set(job.Result, out, formats, inputs=(source,)) as rs:
        result = job.run(source, settings, progress)
        written = write_report(result, rs, formats, progress=progress)
    for line in result.warnings:
        click.echo(f"contactres: warning: {line}", err=True)
    click.echo(f"{source.name} ({result.conventions['reader']}): κ and ωξ per contact, N/m")
    for n, part in result.stiffness.groupby("overtone"):
        click.echo(
            f"  n = {n}: {len(part)} points, median κ = {part['kappa_N_per_m'].median():.6g} N/m, "
            f"median ωξ = {part['omega_xi_N_per_m'].median():.6g} N/m"
        )
    click.echo(wrote_line(written, out))
