"""CLI: ``contactres contact`` (Hertz contact of a rigid sphere on a crystal face: normal and
tangential stiffness, static or at a frequency)."""

from __future__ import annotations

import click

from ._app import main
from ._common import RangeType, emit, format_option
from ._crystal_face import crystal_face, crystal_face_options


def _degrees(ctx, param, value) -> float:
    """``--direction`` as typed: a number in degrees, or an angle with its unit (``30deg``,
    ``0.52rad``), converted with pint as every option's unit (issue 30)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        pass
    from ..errors import ContactresInputError
    from ..typed_units import has_unit, to_si

    if isinstance(value, str) and has_unit(value):
        try:
            return to_si(value, "deg", "--direction")
        except ContactresInputError as exc:
            raise click.BadParameter(str(exc)) from None
    raise click.BadParameter(f"{value!r} is not an angle (degrees, or with its unit: 30deg)")


@main.command(short_help="Hertz contact of a rigid sphere on a crystal face (paper 1).")
@crystal_face_options()
@click.option(
    "--radius",
    type=RangeType("sphere_radius"),
    required=True,
    help="Sphere radius R, m (a number, START:STOP:NUM or a comma list).",
)
@click.option(
    "--force",
    # F = 0 is the unloaded contact (a = 0), the natural start of a load table.
    type=RangeType("force", allow_zero=True),
    required=True,
    help="Normal force F, N (a number, START:STOP:NUM or a comma list).",
)
@click.option(
    "--frequency",
    type=RangeType("frequency", allow_zero=True),
    default=None,
    help="Oscillation frequency f, Hz (a number, START:STOP:NUM or a comma list; needs the "
    "density: --crystal). Adds the exact dynamic normal stiffness (lossless solid), and with "
    "--tangential the dynamic tangential one. Without it: static only.",
)
@click.option(
    "--tangential",
    is_flag=True,
    help="Add the tangential stiffness K_t of the contact (rigid disk of radius a translating "
    "along --direction, relaxed contact: no normal traction).",
)
@click.option(
    "--direction",
    default="0",
    show_default=True,
    callback=_degrees,
    help="Direction of the tangential motion from the surface x axis (--inplane): degrees, "
    "or with its unit (30deg, 0.52rad).",
)
@click.option(
    "--coating",
    multiple=True,
    metavar="MATERIAL:THICKNESS",
    help="A film on the face, thickness in m or with its unit (e.g. pmma:250e-9 or pmma:250nm); "
    "repeat for more layers, top first. MATERIAL: pmma (viscoelastic: static columns use its "
    "1 Hz storage modulus, dynamic ones its modulus at --frequency) or an isotropic solid of "
    "`contactres crystals` (fused-silica, soda-lime-glass, Si3N4). Adds the columns coating "
    "and film_share.",
)
@format_option()
def contact(radius, force, frequency, tangential, direction, coating, fmt, **face):
    """Hertz contact of a rigid sphere on a crystal face (paper 1, Eqs. 1-4).

    Prints the contact radius (m), the semi-axes a >= b of the contact ellipse (m), its
    ellipticity b/a and orientation (major axis, degrees from the surface x axis towards y), the
    peak (centre) pressure p0 (Pa), the indentation depth (m), the static contact stiffness
    K_sa = dF/dw (N/m) and the indentation modulus M (Pa; the E* of the isotropic solid that
    gives nearly the same contact). Radius, force and frequency broadcast: give one of them as a
    range for a table. On faces without 3- or 4-fold symmetry (e.g. 011) the contact is an
    ellipse (a note says so) and the contact radius is √(ab); these numbers do not depend on
    --inplane (but the orientation, measured from it). Hertz holds for a contact small
    against the sphere: rows with a/R > 0.1 get a flags column ("Hertz approximate", values
    kept), rows with a/R > 0.5 are left empty (most likely a radius or force in the wrong unit).

    --direction needs --tangential. --frequency adds the exact dynamic normal stiffness
    K_da = K_sa DCSF (real and imaginary parts, N/m, and k_s a = ω a √(ρ/C44)); --tangential
    adds the tangential stiffness of the contact, static (Mindlin 8Ga/(2 − ν) on an isotropic
    solid) or at --frequency (real and imaginary parts and the radiation loss tangent
    Im K/Re K). --crystal quartz-AT is the AT-cut quartz plate of a QCM (x = the crystal's X
    axis, its shear direction).

    --coating puts films on the face (top first): the contact is then solved on the layered
    solid (axisymmetric), with film_share = 1 − K_sa/K_sa(bare); at --frequency the dynamic
    normal and (with --tangential) tangential stiffness are those of the layered flat punch of
    radius a, the same columns as on a bare face. For instance 250 nm of PMMA on fused silica:
    --crystal fused-silica --coating pmma:250e-9.

    \b
    Example: contactres contact --crystal quartz-AT --radius 5e-3 --force 1e-3 --tangential \\
        --frequency 15e6
    """

    from ..jobs import contact as job

    m = crystal_face(**face)
    settings = job.Settings(radius, force, frequency, tangential, direction, tuple(coating))
    result = job.run(m, settings)
    emit(result.table, fmt)
    for message in result.warnings:  # the job's reservations: warnings, as every command says
        click.echo(_note(message, "warning"), err=True)
    if not result.circular and "ellipticity" in result.table:
        row = result.table.iloc[0]
        click.echo(
            _note(
                f"surface {_face_name(face)} has no 3- or 4-fold symmetry: the contact is "
                f"elliptic (b/a = {row['ellipticity']:.4g}, major axis at "
                f"{row['orientation_deg']:.4g} deg from x); contact_radius_m is sqrt(ab)"
            ),
            err=True,
        )
    elif not result.circular:  # coated: the axisymmetric (circular) approximation
        click.echo(
            _note(
                f"surface {_face_name(face)} has no 3- or 4-fold symmetry: the contact is "
                f"slightly elliptic (relative 2nd harmonic of the compliance "
                f"{result.noncircularity:.3g}); the circular result on the coating is an "
                "approximation"
            ),
            err=True,
        )


def _face_name(face: dict) -> str:
    """The face as the user chose it (the AT cut has its own name)."""
    from ._crystal_face import AT_CUT_NAMES

    crystal = face.get("crystal")
    if crystal is not None and crystal.strip().lower() in AT_CUT_NAMES:
        return "of the AT cut"
    return str(face["surface"])


def _note(message: str, kind: str = "note") -> str:
    """A note (or, ``kind`` "warning", a warning) for stderr, with the prefix every command
    uses (``contactres: note: ``): one line if it fits 100 columns, else broken after its "; "
    clauses (the what, then the advice) and, where a clause is still wider, between its words;
    the continuations indented."""
    import textwrap

    line = f"contactres: {kind}: {message}"
    if len(line) <= 100:
        return line
    clauses = line.replace("; ", ";\n").splitlines()
    wrapped = [
        textwrap.fill(
            c,
            100,
            initial_indent="" if i == 0 else "  ",
            subsequent_indent="  ",
            break_on_hyphens=False,  # fused-silica, soda-lime-glass, paths stay whole
            break_long_words=False,
        )
        for i, c in enumerate(clauses)
    ]
    return "\n".join(wrapped)
