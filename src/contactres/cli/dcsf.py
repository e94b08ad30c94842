"""CLI: ``contactres dcsf`` (dynamic contact stiffness factor of a sphere on a crystal face)."""

from __future__ import annotations

import click

# The option choices need these names while the command tree is built (and --help printed):
# this import is the one library import of the CLI at module level.
from ..dynamic import MODELS, WAVENUMBERS
from ._app import main
from ._common import MagnitudeType, RangeType, emit, format_option
from ._crystal_face import crystal_face, crystal_face_options


@main.command("dcsf")
@crystal_face_options(
    c44_help="Cubic elastic constant C44, Pa (not needed with --zener: DCSF depends on ratios).",
    inplane_help="Direction of the surface x axis (the R1/WA direction) in cube axes.",
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
    type=RangeType("ka"),
    default="0:2:41",
    show_default=True,
    help="Normalised wave number k a, dimensionless (a = contact radius; START:STOP:NUM or a "
    "comma list).",
)
@click.option(
    "--loss",
    type=MagnitudeType("loss"),
    default="0.02",
    show_default=True,
    help="Loss factor Q^-1 of the constants C (1 + i Q^-1), dimensionless; 0 = lossless limit.",
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
    type=MagnitudeType("rtol"),
    default="1e-6",
    show_default=True,
    help="Target relative accuracy of the DCSF, dimensionless.",
)
@format_option()
def dcsf(model, ka, loss, wavenumber, rtol, fmt, **face):
    """Dynamic contact stiffness factor DCSF = K_da/K_sa of a rigid sphere (paper 1, Eq. 29).

    The complex ratio of the dynamic to the static contact stiffness of a sphere vibrating
    normally on the crystal face, for a displacement condition: R0 (centre), R1 (edge, along
    the surface x axis), SA (their mean), WA (pressure-weighted average along x, Bycroft),
    TP (two-parameter pressure, Tian et al.), WA2D (weighted average over the whole contact).
    Columns: ka, model, re, im (re: stiffness, im: damping, both relative to K_sa).

    exact: the rigid flat punch (uniform displacement under the sphere, Galerkin), the answer
    the approximations try to give. Which model to use: exact (as fast as the others). Of the
    paper's approximations TP is closest to it (max. error 0.2-5 % for k_l a <= 1 at
    A = 0.25-4, nu = 0.25; 3-10 % up to k_l a = 2 for A >= 1, but it turns negative at high
    k a for A <= 0.5); WA and WA2D are 2-40 % off by k_l a = 1 (under 1 % below
    k_l a = 0.3); SA, R1 and R0 are worse (R0 is 2-10 % off already at k_l a = 0.3, SA has a
    pole). Ranking: 'contactres figures paper1' writes paper1_model_ranking.csv.
    """
    import pandas as pd

    from ..dynamic import ALL_MODELS, dcsf_models, prepare

    if face["c44"] is None and (face["zener"] is not None or face["poisson"] is not None):
        face["c44"] = 1.0  # the DCSF depends on the ratios only
    m = crystal_face(**face)
    names = list(ALL_MODELS) if model.lower() == "all" else [model]
    # One kernel table serves every model (--model all shares it, and the far-field basis).
    table = prepare(m, loss, rtol)
    out = dcsf_models(m, ka, names, loss=loss, wavenumber=wavenumber, rtol=rtol, prepared=table)
    frames = [
        pd.DataFrame({"ka": ka, "model": name, "re": v.real, "im": v.imag})
        for name, v in out.items()
    ]
    emit(pd.concat(frames, ignore_index=True), fmt)
