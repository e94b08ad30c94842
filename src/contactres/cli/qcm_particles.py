"""CLI: ``contactres qcm particles DATA --particle-radius R --particle-density RHO --out DIR``.

Attached particles (colloids, bacteria, vesicles, cells) against time from QCM-D shifts over the
overtones (issue 28): per time step the shifts Δf_n and ΔΓ_n of all overtones are fitted with the
load of N particles per area A, each on its contact κ + iωξ (the particle and its contact a
resonator of their own), in paper 2's small-load relation. DATA is an instrument export (QSense,
AWSensors, QCM-I, openQCM; the options of ``qcm stiffness`` say what the file does not) or the tidy
table ``time_s, overtone, df_Hz, dgamma_Hz``.

The results folder is one :class:`contactres.fileio.ResultSet` (whole or not at all):
``particles.csv`` (κ, ξ, coverage, f_coupled with errors per time step; an empty cell is a value
the data do not identify, named in ``flags``), ``shifts.csv`` (the shifts read and the model's),
``particles.json`` (the conventions, constants and equation), the figures
(``particles_overtones.png``, ``particles_plane.png``, ``particles_time.png``) and
``report.html`` (unless ``--report none``).
"""

from __future__ import annotations

from pathlib import Path

import click

from ._app import qcm
from ._common import (
    MagnitudeType,
    emit,
    figure_format_option,
    format_option,
    save_as_option,
    step,
    wrote_line,
)
from ._export_options import conventions, export_options


class MediumName(click.ParamType):
    """A medium of :func:`contactres.resonators.medium_named` (checked when given)."""

    name = "MEDIUM"

    def convert(self, value, param, ctx):
        from ..resonators import medium_named

        try:
            return medium_named(value).name
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


@qcm.command("particles")
@click.argument("data", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    required=True,
    help="Results folder (created if missing): particles.csv, shifts.csv, particles.json, "
    "the figures and report.html.",
)
@click.option(
    "--particle-radius",
    type=MagnitudeType("particle_radius"),
    required=True,
    help="Radius R of the particles, m (e.g. 5e-7 m for spheres 1 µm across).",
)
@click.option(
    "--particle-density",
    type=MagnitudeType("density"),
    required=True,
    help="Density ρ of the particles, kg/m^3 (silica 2200, polystyrene 1050, bacteria ~1100).",
)
@click.option(
    "--fundamental",
    type=MagnitudeType("frequency"),
    help="Fundamental frequency f_F of the quartz, Hz: needed for a tidy table and for a file "
    "of shifts only.",
    show_default="f_n/n from a file of absolute frequencies",
)
@click.option(
    "--rocking",
    type=click.Choice(["free", "locked", "fit"]),
    default="free",
    show_default=True,
    help="Rotation of the particle about its contact: free (no rocking stiffness: a rigidly "
    "attached sphere loads the sensor with 2/7 of its mass), locked (no rotation) or fit (a "
    "rocking stiffness, N m/rad, fitted).",
)
@click.option(
    "--medium",
    type=MediumName(),
    help="Medium around the particles: air or water (its drag and added mass on each "
    "particle; the shifts are against the bare sensor in the same medium).",
    show_default="none: no load of a medium on the particles",
)
@export_options(shifts=True)
@click.option(
    "--noise",
    type=click.FloatRange(min=0.0, min_open=True),
    help="Standard deviation of the noise of Δf_n and ΔΓ_n, Hz: the errors are scaled to it.",
    show_default="estimated from the fit's residuals",
)
@click.option(
    "--zq",
    type=MagnitudeType("impedance"),
    default="8.8e6",
    show_default=True,
    help="Acoustic impedance Z_q of AT-cut quartz, kg m^-2 s^-1.",
)
@click.option(
    "--report",
    type=click.Choice(["html", "none"]),
    default="html",
    show_default=True,
    help="html: also report.html in OUT, one self-contained page (conventions, constants, "
    "flags, the tables' first rows, the figures).",
)
@click.option("--no-figures", is_flag=True, help="Skip the figures.")
@figure_format_option()
@save_as_option()
@format_option()
def particles_command(
    data,
    out,
    particle_radius,
    particle_density,
    fundamental,
    rocking,
    medium,
    reader,
    df_per_overtone,
    dissipation_scale,
    baseline,
    time_unit,
    channel,
    overtone,
    noise,
    zq,
    report,
    no_figures,
    figure_formats,
    save_as,
    fmt,
):
    """Attached particles from QCM-D shifts over the overtones: contact stiffness κ, damping
    ξ, coverage and coupled resonance against time.

    DATA is the text export of a QCM-D instrument (QSense, AWSensors, QCM-I, openQCM) or a
    tidy table with the columns time_s, overtone, df_Hz (Δf_n, Hz, not divided by n) and
    dgamma_Hz (ΔΓ_n, Hz, the half-bandwidth shift), shifts against the bare sensor in the same
    medium. Per time step all overtones are fitted with N particles per area A on contacts κ + iωξ
    (paper 2's Eq. 1 with the particle's inertia): a value the data do not identify is left
    empty in particles.csv and named in its flags. Prints the medians of the identified values
    and the flags; writes particles.csv, shifts.csv, particles.json, the figures and
    report.html into OUT.

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres qcm particles example_particles.csv --particle-radius 5e-7 \\
        --particle-density 2200 --fundamental 5e6 --medium water --out particles
    """
    from ..jobs import qcm_particles as job
    from ..report import report_set, write_report

    source = Path(data)
    settings = job.Settings(
        particle_radius=particle_radius,
        particle_density=particle_density,
        fundamental=fundamental,
        rocking=rocking,
        medium=medium,
        reader=reader,
        conventions=conventions(
            df_per_overtone, dissipation_scale, baseline, time_unit, channel, overtone
        ),
        zq=zq,
        sigma_df=noise,
        sigma_dgamma=noise,
    )
    formats = ("csv", "json", *(() if no_figures else figure_formats))
    formats += (*(("html",) if report == "html" else ()), *save_as)
    progress = lambda text: step("qcm particles", text)  # noqa: E731
    # The folder is checked (and locked) before the data are read: an output error comes first.
    with report_set(job.Result, out, formats, inputs=(source,)) as rs:
        result = job.run(source, settings, progress)
        written = write_report(result, rs, formats, progress=progress)
    for line in result.warnings:
        click.echo(f"contactres: warning: {line}", err=True)
    reader_name = result.conventions.get("reader", "")
    if fmt == "plain":
        click.echo(
            f"{source.name} ({reader_name}): {len(result.particles)} time steps, overtones "
            f"{', '.join(map(str, result.constants['overtones']))}; medians of the identified "
            "values"
        )
    emit(result.summary(), fmt)
    if fmt == "plain":
        click.echo(_noise_line(result.constants))
        inertial = _inertial_line(result)
        if inertial:
            click.echo(inertial)
        click.echo(wrote_line(written, out))


def _noise_line(constants) -> str:
    """The noise of the shifts: stated, or what the fit's residuals imply (σ̂) beside what the
    series' step-to-step differences give independently of the model."""
    if constants.get("sigma_df_Hz") is not None:
        return (
            f"noise stated: {constants['sigma_df_Hz']:.3g} Hz (χ²/dof in particles.json tests it)"
        )
    fit, series = constants.get("noise_fit_Hz"), constants.get("noise_series_Hz")
    text = "noise from the residuals σ̂ = " + ("n/a" if fit is None else f"{fit:.3g} Hz")
    if series is None:
        return (
            text
            + "; no estimate from step-to-step differences (too few steps): --noise tests the fit"
        )
    return text + f"; from step-to-step differences {series:.3g} Hz"


def _inertial_line(result) -> str:
    """How many steps are inertial (the particles standing still) with coverage × κ
    identified: their values are in particles.json only (steps), not in the table above."""
    import numpy as np

    nk = np.asarray(result.steps.get("coverage_kappa_N_per_m3", []), float)
    inertial = np.array(["inertial" in str(f).split(";") for f in result.particles["flags"]])
    count = int(np.sum(inertial & np.isfinite(nk))) if nk.size == inertial.size else 0
    if count == 0:
        return ""
    return (
        f"{count} inertial steps (particles standing still) identify coverage × κ and "
        "coverage × ξ only: in particles.json (steps: coverage_kappa_N_per_m3, "
        "coverage_xi_kg_per_s_m2)"
    )
