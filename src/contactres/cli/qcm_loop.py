"""CLI: ``contactres qcm loop``: Δf(u0), ΔΓ(u0) of a partial-slip contact (paper 2, Eqs. 4-5)."""

from __future__ import annotations

import click

from ._app import qcm
from ._common import MagnitudeType, RangeType, emit, format_option, odd_overtone


@qcm.command("loop")
@click.option(
    "--model",
    type=click.Choice(["cm", "savkoor", "voigt"]),  # contactres.jobs.qcm_loop.MODELS
    default="cm",
    show_default=True,
    help="Cattaneo-Mindlin (Eq. 6), Savkoor (Eqs. 13-14) or a linear Voigt element.",
)
@click.option(
    "--kappa",
    type=MagnitudeType("stiffness"),
    required=True,
    help="Low-amplitude stiffness κ of one contact, N/m.",
)
@click.option(
    "--mu", type=MagnitudeType("friction"), help="Friction coefficient μ, dimensionless (cm)."
)
@click.option(
    "--normal-force",
    type=MagnitudeType("force"),
    help="Normal force per contact F_N, N (cm).",
)
@click.option("--tau", type=MagnitudeType("stress"), help="Sliding traction τ0, Pa (savkoor).")
@click.option(
    "--contact-radius",
    type=MagnitudeType("contact_radius"),
    help="Contact radius a, m (savkoor).",
)
@click.option(
    "--xi",
    type=MagnitudeType("drag"),
    default="0",
    show_default=True,
    help="Linear drag ξ of a dashpot in parallel, kg/s; 0 = none.",
)
@click.option(
    "--plateau",
    type=MagnitudeType("displacement"),
    default="0",
    show_default=True,
    help="Critical displacement d_c, m, below which the contact edge sticks (cm, savkoor).",
)
@click.option(
    "--u0",
    type=RangeType("amplitude"),
    default="0:20e-9:21",
    show_default=True,
    help="Amplitudes u0, m (START:STOP:NUM or a comma list).",
)
@click.option(
    "--fundamental",
    type=MagnitudeType("frequency"),
    default="5e6",
    show_default=True,
    help="Fundamental frequency f_F of the quartz, Hz.",
)
@click.option(
    "--overtone",
    type=MagnitudeType("overtone", integer=True),
    callback=odd_overtone,
    default="3",
    show_default=True,
    help="Overtone order n, dimensionless (odd).",
)
@click.option(
    "--area",
    type=MagnitudeType("area"),
    default="1e-5",
    show_default=True,
    help="Effective area A_eff of the electrode, m^2.",
)
@click.option(
    "--zq",
    type=MagnitudeType("impedance"),
    default="8.8e6",
    show_default=True,
    help="Acoustic impedance Z_q of AT-cut quartz, kg m^-2 s^-1.",
)
@click.option(
    "--n-contacts",
    type=MagnitudeType("contacts", integer=True),
    default="1",
    show_default=True,
    help="Number of equal contacts n_P, dimensionless.",
)
@format_option()
def loop_command(
    model,
    kappa,
    mu,
    normal_force,
    tau,
    contact_radius,
    xi,
    plateau,
    u0,
    fundamental,
    overtone,
    area,
    zq,
    n_contacts,
    fmt,
):
    """Frequency and bandwidth shifts of a QCM against the oscillation amplitude u0.

    Prints u0 (m), Δf and ΔΓ (Hz; ΔΓ is the half-bandwidth) and the complex contact stiffness
    K′, K″ (N/m) of one contact, from the force-displacement loop of the chosen model
    (paper 2, Eqs. 4-5; relative accuracy 1e-9).

    \b
    Example: contactres qcm loop --model cm --kappa 1e5 --mu 0.5 --normal-force 1e-3 \\
        --u0 0:20e-9:11
    """
    from ..jobs import qcm_loop as job

    settings = job.Settings(
        model=model,
        kappa=kappa,
        mu=mu,
        normal_force=normal_force,
        tau=tau,
        contact_radius=contact_radius,
        xi=xi,
        plateau=plateau,
        u0=u0,
        fundamental=fundamental,
        overtone=overtone,
        area=area,
        zq=zq,
        n_contacts=n_contacts,
    )
    result = job.run(None, settings)
    for message in result.warnings:  # the library's small-load check (paper 2, Eq. 1)
        click.echo(f"contactres: warning: {message}", err=True)
    emit(result.table, fmt)
