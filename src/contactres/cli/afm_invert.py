"""CLI: ``contactres afm invert TABLE --out OUT.csv`` (resonances -> k* -> modulus, CR-AFM)."""

from __future__ import annotations

import click

from ..errors import ContactresInputError
from ._app import afm
from ._common import MagnitudeType, computed_rounded, emit, format_option, step
from ._crystal_face import crystal_face
from ._film import coating_options, film_summary, parse_film_range


@afm.command("invert")
@click.argument("table", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output table, CSV (computed columns to 10 significant digits) or, named .npz, a "
    "numpy archive (one array per column, exact doubles; the fast way for maps): the input "
    "columns plus kappa, k_star_N_per_m, tip_position_used, "
    "sigma_N_s_per_m, mode_spread, tip_position_other, kappa_other, E_star_Pa, M_sample_Pa, "
    "contact_radius_m, modulus_method, flags, normalisation (and k_static_N_per_m, k_a, "
    "dcsf_real, dcsf_imag with --crystal; coating, M_film_Pa, film_contact_radius_m, "
    "film_weight, film_verdict with --coating).",
)
@click.option(
    "--normalisation",
    type=click.Choice(["global", "modewise"]),
    default="global",
    show_default=True,
    help="Frequency -> β: global uses f1_free_Hz only (ideal beam, β_n = β1 √(f/f1)); modewise "
    "uses each mode's own free frequency (real levers whose free ratios differ from 6.27, 17.5).",
)
@click.option(
    "--mode-tolerance",
    type=MagnitudeType("mode_tolerance"),
    default="0.05",
    show_default=True,
    help="Relative disagreement of κ between modes, dimensionless, beyond which a row is flagged "
    "inconsistent-modes (three modes with r solved: also picks the crossing the third confirms).",
)
@click.option(
    "--crystal",
    help="The sample, for paper 1's dynamic correction of the Hertz rows (K_static = k*/Re "
    "DCSF, each mode at its own frequency; adds k_static_N_per_m, k_a, dcsf_real, dcsf_imag): "
    "a built-in solid (see 'contactres crystals'), e.g. Si, fused-silica.",
)
@click.option(
    "--surface",
    default="001",
    show_default=True,
    help="Surface normal of the sample (--crystal) or of the substrate (--substrate) in crystal "
    "axes (Miller indices): 001, 011, 111, ...",
)
@click.option(
    "--inplane",
    default=None,
    show_default="[100] projected, or [010]",
    help="Direction of the surface x axis in crystal axes.",
)
@click.option(
    "--loss",
    type=MagnitudeType("loss"),
    default="0",
    show_default=True,
    help="Material loss Q^-1 of the sample for the dynamic correction, dimensionless "
    "(0: lossless).",
)
@coating_options()
@format_option()
def afm_invert(
    table,
    out,
    normalisation,
    mode_tolerance,
    crystal,
    surface,
    inplane,
    loss,
    coating,
    substrate,
    film_range,
    min_film_weight,
    fmt,
):
    """Contact stiffness and modulus of every row (point or map pixel) of a CR-AFM table.

    TABLE gives per row the free-lever resonances (f1_free_Hz ...), the spring constant at the
    free end k_c_N_per_m (3EI/L³), the tip position r = L1/L (blank: solved from two modes,
    the largest crossing r in [0.5, 1]), the contact resonances fc1_Hz ... (those given are the
    modes used) and optional Q factors, lateral spring, tip height, tilt (tilt_deg: degrees
    from the sample's surface to the lever, positive with the free end nearer the sample, the
    usual mounting); for the modulus either
    tip_radius_m and load_N (Hertz, E* = √(k*³/6RP)) or a reference sample (fc1_ref_Hz,
    M_ref_Pa; a second one fits the exponent), and M_tip_Pa. Other columns are copied to OUT.
    Euler-Bernoulli lever, k_c the end stiffness (U. Rabe et al., Rev. Sci. Instrum. 67, 3281
    (1996), renormalised by r³). With three modes and r blank, the third picks the crossing
    it confirms; with two, the other crossing is in tip_position_other and kappa_other;
    mode_spread says how far the modes disagree on κ. A contact resonance at the free one
    (within 1e-6 of f either way) is no contact: κ = 0, flag no-contact. With Q factors the
    contact is a spring and a dashpot at the mode's complex frequency. With --crystal (the
    sample, and --surface) paper 1's dynamic correction is applied to the Hertz rows and
    reported (k_static_N_per_m, k_a, dcsf_real, dcsf_imag): every mode is corrected at its
    own frequency, K_static = k*/Re DCSF (J. Tian, Am. J. Eng. Appl. Sci. 3, 56 (2010),
    Eq. 29, exact model). Writes OUT atomically; prints a summary.
    TABLE may also be a numpy archive (.npz, one array per column, as --out x.npz writes it):
    a map read and written in binary skips the CSV's text, most of the time of a large map.

    With --coating MATERIAL:THICKNESS and --substrate NAME (its face: --surface, --inplane)
    every Hertz row's k* is also turned into the film's indentation modulus M_film_Pa with the
    exact layered contact (tip radius, load and tip modulus of the row): the film's
    material gives its Poisson's ratio, its modulus is searched in --film-range.
    film_verdict says whether the film is resolved (film), too thin for the tip
    (film_weight below --min-film-weight: no modulus), too thick (the same as the
    homogeneous inversion M_sample_Pa) or its modulus is outside the range (no modulus).

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres afm invert example_afm.csv --out afm_moduli.csv
    """
    import numpy as np

    from ..fileio import check_output_file, write_csv, write_npz
    from ..jobs import afm_invert as job

    check_output_file(out, inputs=[table])
    binary = str(out).lower().endswith(".npz")
    sample = base = None
    if crystal is not None and substrate is not None:
        raise ContactresInputError(
            "--crystal (the sample, dynamic correction) and --substrate (under a --coating) "
            "exclude each other: the dynamic correction of a coated sample is not available"
        )
    if crystal is not None:  # the built-in solids all carry their density (for k_l = 2πf/c_l)
        sample = crystal_face(crystal, None, None, None, None, None, surface, inplane)
    elif substrate is not None:
        try:
            base = crystal_face(substrate, None, None, None, None, None, surface, inplane)
        except ContactresInputError as exc:  # the name came with --substrate
            raise ContactresInputError(str(exc).replace("--crystal", "--substrate", 1)) from None
    elif inplane is not None or surface != "001":
        raise ContactresInputError(
            "--surface/--inplane describe the sample: give --crystal (or --substrate) too"
        )
    settings = job.Settings(
        normalisation,
        mode_tolerance,
        sample,
        loss,
        coating=tuple(coating),
        substrate=base,
        film_range=parse_film_range(film_range),
        min_film_weight=min_film_weight,
        arrays=binary and fmt == "plain",  # numpy columns from file to file: no pandas
    )
    done = job.run(table, settings, progress=lambda text: step("afm invert", text))
    result = done.table
    if binary:
        write_npz(out, result)
    else:
        write_csv(out, computed_rounded(result, done.input_columns))
    for message in done.warnings:  # e.g. a tip radius above 1 mm: one line, not a refusal
        click.echo(f"contactres: warning: {message}", err=True)
    if fmt != "plain":
        emit(result, fmt)
        return
    k = np.asarray(result["k_star_N_per_m"], dtype=float)
    good = np.isfinite(k)
    flagged = int((result["flags"] != "").sum())
    line = f"{len(result)} rows, {int(good.sum())} with k*"
    if good.any():
        line += f" ({np.min(k[good]):.4g} to {np.max(k[good]):.4g} N/m)"
    M = np.asarray(result["M_sample_Pa"], dtype=float)
    if np.isfinite(M).any():
        known = M[~np.isnan(M)]  # np.nanmedian's value without its import of numpy.ma (np.median
        # imports it to check for masked arrays: ~10 ms of an .npz run)
        middle = np.partition(known, [(known.size - 1) // 2, known.size // 2])
        median = middle[(known.size - 1) // 2 : known.size // 2 + 1].mean()
        line += f", M_sample median {median / 1e9:.4g} GPa"
        # Rows with k* but no modulus (a blank tip radius or load) are counted here, not only
        # left blank in OUT (issue 27's closing campaign).
        if (with_m := int(np.isfinite(M).sum())) < int(good.sum()):
            line += f" in {with_m} of the {int(good.sum())} rows with k*"
    if sample is not None and np.isfinite(result["k_a"]).any():
        change = np.nanmax(np.abs(result["k_static_N_per_m"] / result["k_star_N_per_m"] - 1.0))
        line += (
            f"; dynamic correction: k_l a <= {np.nanmax(result['k_a']):.2g}, "
            f"stiffness changed by <= {change:.2g}"
        )
    elif sample is not None:
        line += "; no dynamic correction (it needs rows with k_c, tip_radius_m and load_N)"
    click.echo(f"{line}; {flagged} flagged ({normalisation} normalisation); wrote {out}")
    if done.coating is not None:
        click.echo(film_summary(result, done.coating))
        for message in done.coating.get("notes", ()):  # Hertz's a/R limit: one line each
            click.echo(f"contactres: warning: {message}", err=True)
