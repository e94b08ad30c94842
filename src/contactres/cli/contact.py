"""CLI: ``contactres contact`` (static Hertz contact of a rigid sphere on a crystal face)."""

from __future__ import annotations

import click

from ._app import main
from ._common import RangeType, emit, format_option
from ._crystal_face import crystal_face, crystal_face_options


@main.command()
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
@format_option()
def contact(radius, force, fmt, **face):
    """Static Hertz contact of a rigid sphere on a crystal face (paper 1, Eqs. 1-4).

    Prints the contact radius a (m), the peak (centre) pressure p0 (Pa), the indentation depth
    (m), the static contact stiffness K_sa = dF/dw (N/m) and the indentation modulus M (Pa; the
    E* of the isotropic solid that gives the same contact). Radius and force broadcast: give one
    of them as a range for a table. On faces without 3- or 4-fold symmetry (e.g. 011) the true
    contact is slightly elliptic and the circular result is an approximation (a note says so).
    """
    import numpy as np
    import pandas as pd

    from ..normal.anisotropic import sphere_contact

    m = crystal_face(**face)
    try:
        R, F = np.broadcast_arrays(radius, force)
    except ValueError:
        raise ValueError(
            f"--radius ({len(radius)} values) and --force ({len(force)} values) must have the "
            "same number of values, or one of them a single value"
        ) from None
    c = sphere_contact(m, R, F)
    table = pd.DataFrame(
        {
            "radius_m": R,
            "force_N": F,
            "contact_radius_m": c.contact_radius,
            "peak_pressure_Pa": c.peak_pressure,
            "depth_m": c.depth,
            "stiffness_N_per_m": c.stiffness,
            "indentation_modulus_Pa": c.indentation_modulus,
        }
    )
    emit(table, fmt)
    if not c.circular:
        click.echo(
            f"note: surface {face['surface']} has no 3- or 4-fold symmetry: the contact is "
            f"slightly elliptic (relative 2nd harmonic of the compliance "
            f"{c.noncircularity:.3g}); the circular Hertz result is an approximation",
            err=True,
        )
