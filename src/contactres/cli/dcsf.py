"""CLI: ``contactres dcsf`` (dynamic contact stiffness factor of a sphere on a crystal face)."""

from __future__ import annotations

import click

# The option choices need these names while the command tree is built (and --help printed):
# this import is the one library import of the CLI at module level.
from ..errors import ContactresInputError
from ._app import main
from ._common import MagnitudeType, RangeType, emit, format_option, step
from ._crystal_face import crystal_face, crystal_face_options

# The choices of --model and --wavenumber: contactres.dynamic's MODELS and WAVENUMBERS, written
# out so that building the command tree (every command's, 'qcm analyze' too) imports no module
# of contactres.dynamic; tests/test_startup.py checks that they are the library's names.
MODEL_CHOICES = ("R0", "R1", "SA", "WA", "TP", "WA2D")
WAVENUMBER_CHOICES = ("longitudinal", "shear")

# The options that together give k a from a physical contact (instead of --ka).
_CONTACT_OPTIONS = ("radius", "force", "frequency")


@main.command("dcsf", short_help="Dynamic contact stiffness factor of a rigid sphere (paper 1).")
@crystal_face_options(
    c44_help="Cubic elastic constant C44, Pa (not needed with --zener: DCSF depends on ratios).",
    inplane_help="Direction of the surface x axis (the R1/WA direction) in cube axes.",
)
@click.option(
    "--model",
    default="exact",
    show_default=True,
    type=click.Choice([*MODEL_CHOICES, "exact", "all"], case_sensitive=False),
    help="Displacement condition, 'exact' (rigid flat punch, recommended) or 'all' (every one).",
)
@click.option(
    "--ka",
    type=RangeType("ka"),
    default="0:2:41",
    show_default=True,
    help="Normalised wave number k a, dimensionless (a = contact radius; START:STOP:NUM or a "
    "comma list). Not with --radius/--force/--frequency, which give k a.",
)
@click.option(
    "--radius",
    type=RangeType("sphere_radius"),
    default=None,
    help="Sphere radius R, m (with --force and --frequency: the physical contact; a number, "
    "START:STOP:NUM or a comma list).",
)
@click.option(
    "--force",
    # F = 0 is the unloaded contact (a = 0, K = 0), as in 'contactres contact'.
    type=RangeType("force", allow_zero=True),
    default=None,
    help="Static normal force F, N (with --radius and --frequency).",
)
@click.option(
    "--frequency",
    type=RangeType("frequency"),
    default=None,
    help="Oscillation frequency f, Hz (with --radius and --force; needs the density: --crystal).",
)
@click.option(
    "--loss",
    type=MagnitudeType("loss"),
    default="0",
    show_default=True,
    help="Loss factor Q^-1 of the constants C (1 + i Q^-1), dimensionless; 0 = lossless solid "
    "(only radiation damping); paper 1's figures use 0.02.",
)
@click.option(
    "--wavenumber",
    type=click.Choice(WAVENUMBER_CHOICES),
    default="longitudinal",
    show_default=True,
    help="k = ω√(ρ/C33) (longitudinal, the paper's k_l a) or ω√(ρ/C44) (shear, k_s a).",
)
@click.option(
    "--rtol",
    type=MagnitudeType("rtol"),
    default="1e-6",
    show_default=True,
    help="Target relative accuracy of the DCSF, dimensionless (checked at run time: rel_error).",
)
@click.option(
    "--coating",
    multiple=True,
    metavar="MATERIAL:THICKNESS",
    help="A film on the face, thickness in m or with its unit (e.g. pmma:250e-9 or pmma:250nm); "
    "repeat for more layers, top first (as 'contactres contact --coating'). The DCSF is then "
    "that of the layered punch, a function of f and a separately (not of k a alone): needs "
    "--radius, --force and --frequency; model exact, no --loss (a pmma film carries its own).",
)
@format_option()
@click.pass_context
def dcsf(ctx, model, ka, radius, force, frequency, loss, wavenumber, rtol, coating, fmt, **face):
    """Dynamic contact stiffness factor DCSF = K_da/K_sa of a rigid sphere (paper 1, Eq. 29).

    The complex ratio of the dynamic to the static contact stiffness of a sphere vibrating
    normally on the crystal face, for a displacement condition: R0 (centre), R1 (edge, along
    the surface x axis), SA (their mean), WA (pressure-weighted average along x, Bycroft),
    TP (two-parameter pressure, Tian et al.), WA2D (weighted average over the whole contact).
    Columns: ka, model, re, im (re: stiffness, im: damping, both relative to K_sa), rel_error
    (the estimated relative error: each value is checked against a refined evaluation, and
    refined where it misses --rtol), flags (not-converged: still above --rtol after two
    refinements; negative-damping: Im < 0, which R0, SA and WA reach at high k a and no
    passive contact has; each also noted in one line on stderr), then the face's C33, C44
    (Pa) and wave speeds v_l = √(C33/ρ), v_s = √(C44/ρ) (m/s); the plain format prints these
    as a '# ' line instead. Defaults: model exact, lossless solid.

    With --radius, --force and --frequency (all three) k a comes from the static Hertz contact
    (contact radius a) at that frequency, and the columns add R, F, f, a, K_sa and the dynamic
    stiffness K = K_sa DCSF (re and im, N/m).

    With --coating (films on the face, and --radius, --force, --frequency) the DCSF is the
    layered rigid punch's at the static contact radius on the coated face and at f: on a
    stack it depends on the frequency and the contact radius separately, not on k a alone
    (ka is then the substrate's, for orientation); a pmma film has no static limit, its K_sa
    uses its 1 Hz storage modulus (a note says so). Columns add coating.

    exact: the rigid flat punch (uniform displacement under the sphere, Galerkin), the answer
    the approximations try to give. Which model to use: exact (as fast as the others). Of the
    paper's approximations TP is closest to it (max. error 0.2-5 % for k_l a <= 1 at
    A = 0.25-4, nu = 0.25; 3-10 % up to k_l a = 2 for A >= 1, but it turns negative at high
    k a for A <= 0.5); WA and WA2D are 2-40 % off by k_l a = 1 (under 1 % below
    k_l a = 0.3); SA, R1 and R0 are worse (R0 is 2-10 % off already at k_l a = 0.3, SA has a
    pole, R0 has negative damping near k_l a = 1.8-2). R1, SA, WA and TP depend on the
    in-plane axis --inplane (up to 12 % on Cu(001)); exact and WA2D do not. Ranking:
    'contactres figures paper1' writes paper1_model_ranking.csv.

    \b
    Example: contactres dcsf --crystal Cu --surface 111 --model all --ka 0:1:5
    """
    from ..dynamic import ALL_MODELS
    from ..jobs import dcsf as job

    contact_options = {"radius": radius, "force": force, "frequency": frequency}
    given = [name for name in _CONTACT_OPTIONS if contact_options[name] is not None]
    physical = bool(given)
    if physical and len(given) < len(_CONTACT_OPTIONS):
        missing = [f"--{n}" for n in _CONTACT_OPTIONS if n not in given]
        raise click.UsageError(
            f"--radius, --force and --frequency go together: missing {', '.join(missing)}", ctx
        )
    ka_typed = ctx.get_parameter_source("ka") is not click.core.ParameterSource.DEFAULT
    if coating and not physical:
        raise ContactresInputError(
            "--coating: on a coated face the DCSF depends on f and a separately, not on k a "
            "alone: give --radius, --force and --frequency (not --ka)"
        )
    if physical and ka_typed:
        raise click.UsageError(
            "give --ka or --radius/--force/--frequency (which give k a), not both", ctx
        )
    ratios_only = face["c44"] is None and (face["zener"] is not None or face["poisson"] is not None)
    if ratios_only:
        face["c44"] = 1.0  # the DCSF depends on the ratios only
    m = crystal_face(**face)
    if physical:
        if ratios_only or m.density is None:
            raise click.UsageError(
                "--radius/--force/--frequency need the elastic constants in Pa and the "
                "density: use --crystal NAME",
                ctx,
            )
        _check_same_size(radius, force, frequency)
    settings = job.Settings(
        models=tuple(ALL_MODELS) if model.lower() == "all" else (model,),
        ka=None if physical else ka,
        radius=radius,
        force=force,
        frequency=frequency,
        loss=loss,
        wavenumber=wavenumber,
        rtol=rtol,
        constants_in_pa=not ratios_only,
        coating=tuple(coating),
    )
    result = job.run(m, settings, progress=lambda text: step("dcsf", text))
    for line in result.warnings:
        click.echo(f"contactres: warning: {line}", err=True)
    table = result.table
    if fmt == "plain":
        click.echo("# " + _face_line(result.face))
    else:
        for key, value in result.face.items():
            table[key] = value
    emit(table, fmt)


def _check_same_size(radius, force, frequency) -> None:
    """--radius, --force and --frequency broadcast (the same number of values, or one)."""
    import numpy as np

    try:
        np.broadcast_shapes(radius.shape, force.shape, frequency.shape)
    except ValueError:
        raise ContactresInputError(
            f"--radius ({radius.size}), --force ({force.size}) and --frequency ({frequency.size}"
            ") must have the same number of values, or a single value"
        ) from None


def _face_line(speeds: dict) -> str:
    """The '# ' header of the plain format: the constants and wave speeds of the face."""
    import math

    if math.isnan(speeds["C33_Pa"]):
        return (
            f"face: C33/C44 = {speeds['C33_over_C44']:.6g} (constants given as ratios: "
            "no C33, C44 in Pa, no wave speeds)"
        )
    text = f"face: C33 = {speeds['C33_Pa']:.6g} Pa, C44 = {speeds['C44_Pa']:.6g} Pa"
    if math.isnan(speeds["v_l_m_per_s"]):
        return text + " (no density: no wave speeds)"
    return (
        text + f", v_l = sqrt(C33/rho) = {speeds['v_l_m_per_s']:.6g} m/s, "
        f"v_s = sqrt(C44/rho) = {speeds['v_s_m_per_s']:.6g} m/s"
    )
