"""CLI: ``contactres contact`` (static Hertz contact of a rigid sphere on a crystal face)."""

from __future__ import annotations

import re

import click
import numpy as np
import pandas as pd

from ..materials import Material
from ..normal.anisotropic import sphere_contact
from ._app import main
from ._common import RANGE, emit, format_option


def parse_direction(text: str, name: str = "surface") -> tuple[float, float, float]:
    """Parse Miller-like indices: ``001``, ``1-10``, ``-1 1 0`` or ``1,1,1``."""
    s = str(text).strip()
    try:
        if "," in s or " " in s:
            parts = s.replace(",", " ").split()
        elif re.fullmatch(r"(-?\d){3}", s):
            parts = re.findall(r"-?\d", s)
        else:
            raise ValueError
        if len(parts) != 3:
            raise ValueError
        v = tuple(float(p) for p in parts)
    except ValueError:
        raise ValueError(
            f"--{name} {text!r} is not a direction: give three indices such as 001, 1-10, "
            "'1 1 1' or 1,1,0"
        ) from None
    if not np.all(np.isfinite(v)) or not any(v):
        raise ValueError(f"--{name} {text!r} must be three finite numbers, not all zero")
    return v


def material_from_options(crystal, c11, c12, c44, zener, poisson) -> Material:
    """The crystal (cube-axis frame) chosen by ``--crystal`` or the elastic-constant options."""
    by_constants = c11 is not None or c12 is not None
    by_ratios = zener is not None or poisson is not None
    chosen = sum([crystal is not None, by_constants, by_ratios])
    if chosen != 1:
        raise ValueError(
            "give exactly one of: --crystal NAME, --c11/--c12/--c44 (Pa), or "
            "--zener/--poisson/--c44 (Pa)"
        )
    if crystal is not None:
        if c44 is not None:
            raise ValueError("--c44 cannot be combined with --crystal")
        return Material.crystal(crystal)
    missing = [
        n
        for n, v in (
            ("--c11", c11) if by_constants else ("--zener", zener),
            ("--c12", c12) if by_constants else ("--poisson", poisson),
            ("--c44", c44),
        )
        if v is None
    ]
    if missing:
        raise ValueError(f"missing {', '.join(missing)}")
    if by_constants:
        return Material.cubic(c11, c12, c44)
    return Material.cubic_from_ratios(zener, poisson, c44=c44)


@main.command()
@click.option("--crystal", help="Built-in cubic crystal (see 'contactres crystals'), e.g. Cu.")
@click.option("--c11", type=float, help="Cubic elastic constant C11, Pa.")
@click.option("--c12", type=float, help="Cubic elastic constant C12, Pa.")
@click.option("--c44", type=float, help="Cubic elastic constant C44, Pa.")
@click.option("--zener", type=float, help="Zener ratio A = 2 C44/(C11 - C12) (with --poisson).")
@click.option("--poisson", type=float, help="ν = C12/(C11 + C12) of the cubic crystal.")
@click.option(
    "--surface",
    default="001",
    show_default=True,
    help="Surface normal in cube axes (Miller indices): 001, 011, 111, 1-10, '1 2 3', ...",
)
@click.option(
    "--inplane",
    default=None,
    help="Direction of the surface x axis in cube axes (default: [100] projected, or [010]).",
)
@click.option("--radius", type=RANGE, required=True, help="Sphere radius R, m (or START:STOP:NUM).")
@click.option("--force", type=RANGE, required=True, help="Normal force F, N (or START:STOP:NUM).")
@format_option()
def contact(crystal, c11, c12, c44, zener, poisson, surface, inplane, radius, force, fmt):
    """Static Hertz contact of a rigid sphere on a crystal face (paper 1, Eqs. 1-4).

    Prints the contact radius a (m), the peak (centre) pressure p0 (Pa), the indentation depth
    (m), the static contact stiffness K_sa = dF/dw (N/m) and the indentation modulus M (Pa; the
    E* of the isotropic solid that gives the same contact). Radius and force broadcast: give one
    of them as a range for a table. On faces without 3- or 4-fold symmetry (e.g. 011) the true
    contact is slightly elliptic and the circular result is an approximation (a note says so).
    """
    m = material_from_options(crystal, c11, c12, c44, zener, poisson)
    normal = parse_direction(surface, "surface")
    x = None if inplane is None else parse_direction(inplane, "inplane")
    m = m.rotated(normal, x)
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
            "contact_radius_m": np.broadcast_to(c.contact_radius, R.shape),
            "peak_pressure_Pa": np.broadcast_to(c.peak_pressure, R.shape),
            "depth_m": np.broadcast_to(c.depth, R.shape),
            "stiffness_N_per_m": np.broadcast_to(c.stiffness, R.shape),
            "indentation_modulus_Pa": c.indentation_modulus,
        }
    )
    emit(table, fmt)
    if not c.circular:
        click.echo(
            f"note: surface {surface} has no 3- or 4-fold symmetry: the contact is slightly "
            f"elliptic (relative 2nd harmonic of the compliance {c.noncircularity:.3g}); the "
            "circular Hertz result is an approximation",
            err=True,
        )
