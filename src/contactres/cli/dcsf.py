"""CLI: ``contactres dcsf`` (dynamic contact stiffness factor of a sphere on a crystal face)."""

from __future__ import annotations

import click
import pandas as pd

from ..dynamic import ALL_MODELS, MODELS, WAVENUMBERS, dcsf_models
from ._app import main
from ._common import RANGE, emit, format_option
from .contact import material_from_options, parse_direction


@main.command("dcsf")
@click.option("--crystal", help="Built-in cubic crystal (see 'contactres crystals'), e.g. Cu.")
@click.option("--c11", type=float, help="Cubic elastic constant C11, Pa.")
@click.option("--c12", type=float, help="Cubic elastic constant C12, Pa.")
@click.option("--c44", type=float, help="Cubic elastic constant C44, Pa (not needed with --zener).")
@click.option("--zener", type=float, help="Zener ratio A = 2 C44/(C11 - C12) (with --poisson).")
@click.option("--poisson", type=float, help="ν = C12/(C11 + C12) of the cubic crystal.")
@click.option(
    "--surface",
    default="001",
    show_default=True,
    help="Surface normal in cube axes (Miller indices): 001, 011, 111, ...",
)
@click.option(
    "--inplane",
    default=None,
    help="Direction of the surface x axis (the R1/WA direction) in cube axes.",
)
@click.option(
    "--model",
    default="WA",
    show_default=True,
    type=click.Choice([*MODELS, "exact", "all"], case_sensitive=False),
    help="Displacement condition, 'exact' (rigid flat punch) or 'all' (every one).",
)
@click.option(
    "--ka",
    type=RANGE,
    default="0:2:41",
    show_default=True,
    help="Normalised wave number k a (dimensionless; a = contact radius), START:STOP:NUM.",
)
@click.option(
    "--loss",
    type=float,
    default=0.02,
    show_default=True,
    help="Loss factor Q^-1 of the constants C (1 + i Q^-1); 0 = lossless limit.",
)
@click.option(
    "--wavenumber",
    type=click.Choice(WAVENUMBERS),
    default="longitudinal",
    show_default=True,
    help="k = ω√(ρ/C33) (longitudinal, the paper's k_l a) or ω√(ρ/C44) (shear, k_s a).",
)
@click.option(
    "--rtol",
    type=float,
    default=1e-6,
    show_default=True,
    help="Target relative accuracy of the DCSF.",
)
@format_option()
def dcsf(
    crystal,
    c11,
    c12,
    c44,
    zener,
    poisson,
    surface,
    inplane,
    model,
    ka,
    loss,
    wavenumber,
    rtol,
    fmt,
):
    """Dynamic contact stiffness factor DCSF = K_da/K_sa of a rigid sphere (paper 1, Eq. 29).

    The complex ratio of the dynamic to the static contact stiffness of a sphere vibrating
    normally on the crystal face, for a displacement condition: R0 (centre), R1 (edge, along
    the surface x axis), SA (their mean), WA (pressure-weighted average along x, Bycroft),
    TP (two-parameter pressure, Tian et al.), WA2D (weighted average over the whole contact).
    Columns: ka, model, re, im (re: stiffness, im: damping, both relative to K_sa).

    exact: the rigid flat punch (uniform displacement under the sphere, Galerkin), the answer
    the approximations try to give. Which model to use: exact whenever you can (it costs a few
    times WA); of the paper's approximations WA (and WA2D) stay close to exact up to k_l a ~ 1
    (see 'contactres figures paper1': paper1_model_ranking.csv); R0, SA and TP turn negative
    at high k a (unphysical). Below k_l a ~ 0.3 every model agrees to ~1 %.
    """
    if c44 is None and crystal is None and c11 is None and c12 is None:
        c44 = 1.0  # the DCSF depends on the ratios only
    m = material_from_options(crystal, c11, c12, c44, zener, poisson)
    normal = parse_direction(surface, "surface")
    x = None if inplane is None else parse_direction(inplane, "inplane")
    m = m.rotated(normal, x)
    names = list(ALL_MODELS) if model.lower() == "all" else [model]
    out = dcsf_models(m, ka, names, loss=loss, wavenumber=wavenumber, rtol=rtol)
    frames = [
        pd.DataFrame({"ka": ka, "model": name, "re": v.real, "im": v.imag})
        for name, v in out.items()
    ]
    emit(pd.concat(frames, ignore_index=True), fmt)
