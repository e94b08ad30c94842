"""CLI: ``contactres qcm spectra``: admittance spectra -> the sweep table (Δf, ΔΓ, u0)."""

from __future__ import annotations

import click

from ._app import qcm
from ._common import MagnitudeType, emit_record, format_option, step

_LAYOUTS = ("G/B", "Y-RI", "S11-RI", "Y-MA")


@qcm.command("spectra")
@click.argument("spectra", type=click.Path(exists=True))
@click.option(
    "--out",
    required=True,
    type=click.Path(dir_okay=False),
    help="Sweep table to write (CSV: sweep, amplitude_m, df_Hz, dgamma_Hz, their errors and "
    "the labels), the input of 'contactres qcm analyze'.",
)
@click.option(
    "--fits",
    type=click.Path(dir_okay=False),
    help="Also write the resonance fit of every spectrum (f_r, Γ, errors, flags) to this CSV.",
)
@click.option(
    "--reference",
    show_default="the column 'reference' of the table or index.csv",
    help="Ids of the no-contact reference spectra, comma separated.",
)
@click.option(
    "--layout",
    type=click.Choice(_LAYOUTS),
    help="What the two columns of the folder's delimited spectrum files hold, when their "
    "header does not say it: G/B (S), Y-RI (S), S11-RI, Y-MA (S, degrees).",
)
@click.option(
    "--reference-impedance",
    type=MagnitudeType("reference_impedance"),
    default=50.0,
    show_default=True,
    help="Reference impedance Z0 of S11 in delimited files, Ω (Touchstone files give theirs; "
    "a number in Ω or with its unit, e.g. 75ohm).",
)
@click.option(
    "--two-port",
    type=click.Choice(["S11", "S22", "S21"]),
    help="Which S parameter of the folder's two-port Touchstone files (.s2p) is the crystal's "
    "response: S11 or S22 (reflection: the crystal on port 1 or 2) or S21 (the crystal in "
    "series between the ports).",
)
@click.option(
    "--voltage",
    type=click.Choice(["amplitude", "rms"]),
    default="amplitude",
    show_default=True,
    help="Whether drive_voltage_V is the amplitude (peak) or the rms voltage.",
)
@click.option(
    "--d26",
    type=MagnitudeType("piezo_constant"),
    default=None,
    show_default="3.1e-12, AT-cut, Johannsmann et al. 2021",
    help="Piezoelectric strain constant of the quartz, m/V (or with its unit: 3.1pm/V). The "
    "amplitude is "
    "u0 = 4 d26 Q U/(nπ)², Q = f_r/(2Γ).",
)
@click.option(
    "--calibration",
    type=MagnitudeType("amplitude_calibration"),
    default=None,
    help="Amplitude per drive volt measured on your instrument, m/V (or with its unit: "
    "2nm/V): u0 = this × U "
    "(replaces the d26 formula).",
)
@format_option()
def spectra_command(
    spectra,
    out,
    fits,
    reference,
    layout,
    reference_impedance,
    two_port,
    voltage,
    d26,
    calibration,
    fmt,
):
    """Fit admittance spectra and write the sweep table.

    SPECTRA is a tidy CSV (one row per frequency point: spectrum, frequency_Hz, G_S, B_S, and
    per spectrum drive_voltage_V, overtone, reference, sweep, ramp, experiment,
    normal_force_N, configuration, medium) or a folder of network-analyser files (Touchstone
    .s1p/.y1p/.z1p, .s2p with --two-port, or CSV) with an index.csv (column file + the same
    labels). Every spectrum is fitted for its resonance frequency f_r and half-bandwidth Γ
    (half width at half height of G); Δf and ΔΓ are taken against the reference spectra of
    the same overtone (Δf not divided by n; Γ, not D); the amplitude follows from the drive
    voltage.

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres qcm spectra example_spectra.csv --out sweeps.csv \\
        --fits fits.csv
    """
    from pathlib import Path

    from ..fileio import CSV_FLOAT_FORMAT, check_output_file, neutralised, write_csv, write_text
    from ..jobs import qcm_spectra as job

    # An empty --fits is refused (check_output_file), not taken as "no fits file".
    if fits and Path(fits).resolve() == Path(out).resolve():
        raise click.BadParameter("must name another file than --out", param_hint="'--fits'")
    targets = [check_output_file(out, [spectra])]
    if fits is not None:
        targets.append(check_output_file(fits, [spectra, out]))
    ids = None if reference is None else [x for x in reference.split(",") if x.strip()]
    if reference is not None and not ids:
        raise click.BadParameter("give at least one spectrum id", param_hint="'--reference'")
    settings = job.Settings(
        reference=None if ids is None else tuple(ids),
        layout=layout,
        reference_impedance=reference_impedance,
        voltage=voltage,
        d26=d26,
        calibration=calibration,
        two_port=two_port,
    )
    result = job.run(spectra, settings, progress=lambda text: step("qcm spectra", text))
    rows, fitted, conventions = result.sweeps, result.fits, result.conventions
    # The conventions go into the file as comment lines (the sweep reader skips them); ten
    # significant digits: below every stated error, no floating-point noise.
    header = "".join(f"# {k}: {v}\n" for k, v in conventions.items())
    body = neutralised(rows).to_csv(index=False, float_format=CSV_FLOAT_FORMAT)
    write_text(targets[0], header + body)
    if fits is not None:
        write_csv(targets[1], fitted, index=False, float_format=CSV_FLOAT_FORMAT)
    for line in result.warnings:
        click.echo(f"contactres: warning: {line}", err=True)
    record = {
        "spectra": len(fitted),
        "references": int(len(fitted) - len(rows) - len(result.warnings)),
        "left_out": len(result.warnings),
        "sweeps": int(rows["sweep"].nunique()),
        "points": len(rows),
        "amplitude_range_m": [float(rows["amplitude_m"].min()), float(rows["amplitude_m"].max())],
        **{f"convention_{k}": v for k, v in conventions.items()},
        "wrote": [str(t) for t in targets],
    }
    if fmt != "plain":
        emit_record(record, fmt)
        return
    click.echo(
        f"{record['spectra']} spectra: {record['points']} points of {record['sweeps']} sweeps, "
        f"{record['references']} references, {record['left_out']} left out; amplitudes "
        f"{record['amplitude_range_m'][0]:.3g} to {record['amplitude_range_m'][1]:.3g} m"
    )
    for key, text in conventions.items():
        click.echo(f"  {key}: {text}")
    click.echo(f"wrote {', '.join(record['wrote'])}")
