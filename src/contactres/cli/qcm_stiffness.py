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

import math
from pathlib import Path

import click

from ._app import qcm
from ._common import MagnitudeType, odd_overtone, step


def reader_names() -> tuple[str, ...]:
    """The names of the export readers, in the order they are tried: those of the registry
    (``contactres.measurements.readers.exports.EXPORT_READERS``; imported without pandas)."""
    from ..measurements.readers.exports import EXPORT_READERS

    return tuple(r.name for r in EXPORT_READERS)


def __getattr__(name: str):
    """``COLUMN_UNITS`` (the units of stiffness.csv's columns) is the job's and
    ``READER_NAMES`` (:func:`reader_names`) the registry's, loaded on use."""
    if name == "COLUMN_UNITS":
        from ..jobs.qcm_stiffness import COLUMN_UNITS

        return COLUMN_UNITS
    if name == "READER_NAMES":
        return reader_names()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class ReaderName(click.ParamType):
    """The name of an export reader, checked against the registry when given."""

    name = "NAME"

    def convert(self, value, param, ctx):
        from ..measurements.readers.exports import export_reader

        try:
            return export_reader(value).name
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


class ReaderOption(click.Option):
    """``--reader``, whose help names the export readers of the registry, read when the help is
    shown (building the command imports no reader)."""

    @property
    def help(self) -> str:
        return f"Export format: {', '.join(reader_names())}."

    @help.setter
    def help(self, value) -> None:
        """click sets the help when it builds the option; the text is the registry's."""


class DissipationScale(click.ParamType):
    """What one unit of a D column is: a number in (0, 1] (1e-6 for ppm) or ``ppm``."""

    name = "SCALE"

    def convert(self, value, param, ctx):
        text = str(value).strip().lower()
        try:
            scale = 1e-6 if text == "ppm" else float(text)
        except ValueError:
            self.fail(f"{value!r} is not a number: use 1e-6 (D in ppm) or 1 (D plain)", param, ctx)
        if not (math.isfinite(scale) and 0 < scale <= 1):
            self.fail(
                f"{value!r} is outside (0, 1]: the scale of D is 1e-6 for ppm or 1 for a plain "
                "number",
                param,
                ctx,
            )
        return scale


class Baseline(click.ParamType):
    """``first``, ``as-exported`` or ``window:T0:T1`` (seconds)."""

    name = "BASELINE"

    def convert(self, value, param, ctx):
        from ..measurements.readers.exports import parse_baseline

        try:
            parse_baseline(value)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)
        return str(value).strip().lower()


@qcm.command("stiffness")
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
@click.option(
    "--reader",
    cls=ReaderOption,
    type=ReaderName(),
    show_default="recognised from the header",
)
@click.option(
    "--df-per-overtone/--df-divided-by-n",
    "df_per_overtone",
    default=None,
    help="The file's frequency shifts are Δf_n, Hz, or Δf_n/n, Hz (where its header does not "
    "say; not for absolute frequencies).",
)
@click.option(
    "--dissipation-scale",
    type=DissipationScale(),
    help="What one unit of the file's D column is, dimensionless: 1e-6 (or ppm) for D in "
    "10^-6, 1 for D as a plain number (where the header does not say).",
)
@click.option(
    "--baseline",
    type=Baseline(),
    help="Reference of the shifts: first (first point of each overtone), window:T0:T1 (mean "
    "over T0 <= t <= T1, s) or as-exported (files of shifts).",
    show_default="as-exported for shifts; absolute frequencies need one",
)
@click.option(
    "--time-unit",
    type=click.Choice(["s", "min", "h"]),
    help="Unit of the file's time column: seconds, minutes or hours (where the header does "
    "not say).",
)
@click.option(
    "--channel",
    help="Sensor or channel to read from a multi-sensor export (QSense 1-4, QCM-I A-D).",
)
@click.option(
    "--overtone",
    type=MagnitudeType("overtone", integer=True),
    callback=odd_overtone,
    help="Overtone order n, dimensionless (odd): that of a single-overtone openQCM log, or "
    "the one to keep.",
    show_default="all in the file",
)
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
        contactres qcm stiffness run.txt --df-divided-by-n --dissipation-scale 1e-6
        --time-unit s --fundamental 4.95e6 --area 2e-5 --n-contacts 3 --out run-stiffness
    """
    from ..jobs import qcm_stiffness as job
    from ..report import report_set, write_report

    source = Path(export)
    conventions = {
        "df_divided_by_n": None if df_per_overtone is None else not df_per_overtone,
        "dissipation_scale": dissipation_scale,
        "baseline": baseline,
        "time_unit": time_unit,
        "channel": channel,
        "overtone": overtone,
        "fundamental": fundamental,
    }
    settings = job.Settings(area, n_contacts, reader, conventions, zq)
    progress = lambda text: step("qcm stiffness", text)  # noqa: E731
    # The folder is checked (and locked) before the export is read: an output error comes first.
    with report_set(job.Result, out, inputs=(source,)) as rs:
        result = job.run(source, settings, progress)
        written = write_report(result, rs, progress=progress)
    for line in result.warnings:
        click.echo(f"contactres: warning: {line}", err=True)
    click.echo(f"{source.name} ({result.conventions['reader']}): κ and ωξ per contact, N/m")
    for n, part in result.stiffness.groupby("overtone"):
        click.echo(
            f"  n = {n}: {len(part)} points, median κ = {part['kappa_N_per_m'].median():.6g}, "
            f"median ωξ = {part['omega_xi_N_per_m'].median():.6g}"
        )
    click.echo(f"wrote {len(written)} files into {out}/")
