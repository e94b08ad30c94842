"""CLI: ``contactres afm invert TABLE --out OUT.csv`` (resonances -> k* -> modulus, CR-AFM)."""

from __future__ import annotations

from pathlib import Path

import click

from ._app import afm
from ._common import emit, format_option


@afm.command("invert")
@click.argument("table", type=click.Path(dir_okay=False))
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output CSV: the input columns plus kappa, k_star_N_per_m, tip_position_used, "
    "sigma_N_s_per_m, E_star_Pa, M_sample_Pa, contact_radius_m, flags.",
)
@click.option(
    "--normalisation",
    type=click.Choice(["global", "modewise"]),
    default="global",
    show_default=True,
    help="Frequency -> β: global uses f1_free_Hz only (ideal beam, β_n = β1 √(f/f1)); modewise "
    "uses each mode's own free frequency (real levers whose free ratios differ from 6.27, 17.5).",
)
@format_option()
def afm_invert(table, out, normalisation, fmt):
    """Contact stiffness and modulus of every row (point or map pixel) of a CR-AFM table.

    TABLE gives per row the free-lever resonances (f1_free_Hz ...), the spring constant at the
    free end k_c_N_per_m (3EI/L³), the tip position r = L1/L (blank: solved from two modes,
    the largest crossing r in [0.5, 1]), the contact resonances fc1_Hz ... (those given are the
    modes used) and optional Q factors, lateral spring, tip height, tilt; for the modulus either
    tip_radius_m and load_N (Hertz, E* = √(k*³/6RP)) or a reference sample (fc1_ref_Hz,
    M_ref_Pa; a second one fits the exponent), and M_tip_Pa. Other columns are copied to OUT.
    Euler-Bernoulli lever, k_c the end stiffness (U. Rabe et al., Rev. Sci. Instrum. 67, 3281
    (1996), renormalised by r³). Writes OUT atomically; prints a summary.
    """
    import numpy as np

    from ..analysis.resonance_tables import invert_afm_table
    from ..fileio import check_output_file, write_csv
    from ..measurements.resonances import AFM_TABLE, read_resonance_table

    check_output_file(out, inputs=[table])
    checked = read_resonance_table(table, AFM_TABLE)
    result = invert_afm_table(checked, str(Path(table)), normalisation=normalisation)
    write_csv(out, result)
    if fmt != "plain":
        emit(result, fmt)
        return
    k = result["k_star_N_per_m"].to_numpy(float)
    good = np.isfinite(k)
    flagged = int((result["flags"] != "").sum())
    line = f"{len(result)} rows, {int(good.sum())} with k*"
    if good.any():
        line += f" ({np.min(k[good]):.4g} to {np.max(k[good]):.4g} N/m)"
    M = result["M_sample_Pa"].to_numpy(float)
    if np.isfinite(M).any():
        line += f", M_sample median {np.nanmedian(M) / 1e9:.4g} GPa"
    click.echo(f"{line}; {flagged} flagged ({normalisation} normalisation); wrote {out}")
